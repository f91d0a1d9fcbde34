// Serves one kind of request (one ROS 2 service name) for a set of cameras: opens
// <camera namespace>/<service> for each, copies each request out of its sample as it arrives
// and hands it to the handler with the camera it was sent to. Each handler (point queries,
// pose queries, floor calibration) owns one of these.
#pragma once

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <functional>
#include <iostream>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <type_traits>
#include <utility>
#include <vector>

#include "idl/protocol/service_endpoints.h"
#include "service/server/service_config.h"

namespace monocle {

// The cameras that offer a service: those with the role (CameraSetup::floor or ::corner).
inline std::vector<const CameraSetup*> CamerasWith(const std::vector<CameraSetup>& cameras,
                                                   bool (CameraSetup::*has_role)() const) {
  std::vector<const CameraSetup*> out;
  for (const auto& c : cameras) {
    if ((c.*has_role)()) out.push_back(&c);
  }
  return out;
}

// Requests for which `quick` says yes (a pose, a few points) are answered on Cyclone's
// receive thread as they arrive, from a data-available listener: a hand-over to a thread of
// our own cost a wake-up on each request, and bench/service_bench measured the one-point
// round trip at 1.3x ddsperf's with it. The others (a floor calibration, 100 000 points)
// would hold the receive thread, so they queue for the server's own thread.
template <typename Request, typename Reply, typename Value>
class RequestServer {
 public:
  using Server = dds::ServiceServer<Request, Reply>;
  struct Incoming {
    const CameraSetup* camera = nullptr;
    Value value;
    dds::RequestHeader header;
    Server* server = nullptr;  // to reply on
    std::string client;        // who sent it: its participant, or its identity under DDS Security
  };
  using Parse = std::function<Value(const Request&)>;
  using Handle = std::function<void(Incoming&&)>;
  using Quick = std::function<bool(const Value&)>;  // answer on the receive thread
  using Tick = std::function<void()>;               // on the server's thread, every kTick

  static constexpr std::chrono::milliseconds kTick{100};
  // A client is a participant: all request writers of one participant share one budget and
  // one queue, so a client gains nothing by opening more writers. With DDS Security a client
  // is an authenticated identity: all its participants share one budget and one queue, so a
  // client gains nothing by opening more participants either.
  //
  // Requests waiting for the server's thread, per client and in all; beyond these the
  // client's oldest is dropped (as a DDS keep-last history would), so a flood can neither
  // grow memory nor push other clients' requests out. The server's thread takes the clients
  // in turn.
  static constexpr size_t kMaxQueuedPerClient = 8;
  static constexpr size_t kMaxQueued = 64;
  // A new client's first request may come before its reply reader is matched to our reply
  // writer (discovery runs both ways independently) and a volatile reply written now would
  // be lost: such requests wait aside, without holding the thread, until the match (checked
  // every kParkedCheck) or kParkedLimit.
  static constexpr size_t kMaxParked = 64;
  static constexpr std::chrono::milliseconds kParkedCheck{2};
  static constexpr std::chrono::milliseconds kParkedLimit{3000};
  static constexpr size_t kMaxKnownWriters = 4096;
  static constexpr std::chrono::seconds kForgetPeriod{10};
  // Each client may send this many requests a second, in bursts of up to kBurst; more are
  // dropped before any work. A robot asks 100-200 times a second, a client asking in a tight
  // loop ~3000 (one round trip is ~0.3 ms). When many clients ask at once the service's
  // kServiceRequestsPerSecond is shared among those heard in the last second (no less than
  // kMinRequestsPerSecond each): a flood gets its share and no more, from any number of
  // participants, so it cannot starve the others.
  static constexpr double kMaxRequestsPerSecond = 5000;
  static constexpr double kServiceRequestsPerSecond = 4000;
  static constexpr double kMinRequestsPerSecond = 100;
  static constexpr double kBurst = 500;

  // `cameras` must outlive the server. `handle` may run on two threads at once.
  static Result<std::unique_ptr<RequestServer>> Start(
      const std::shared_ptr<dds::Entity>& participant,
      const std::vector<const CameraSetup*>& cameras, const dds_topic_descriptor_t* request_type,
      const dds_topic_descriptor_t* reply_type, const std::string& service, Parse parse,
      Handle handle, Quick quick = nullptr, Tick tick = nullptr) {
    std::unique_ptr<RequestServer> s(new RequestServer());
    s->by_identity_ = dds::UsesSecurity(participant->get());
    s->parse_ = std::move(parse);
    s->handle_ = std::move(handle);
    s->quick_ = std::move(quick);
    s->tick_ = std::move(tick);
    s->thread_ = std::thread([self = s.get()] { self->Run(); });
    for (const CameraSetup* cam : cameras) {
      auto pc = std::make_unique<PerCamera>(PerCamera{cam, nullptr, s.get(), nullptr});
      dds::EndpointQos request_qos = wire::kRequestReaderQos;
      request_qos.accept_from = &RequestServer::OnArrival;
      request_qos.accept_arg = pc.get();
      auto server = Server::Open(participant, request_type, reply_type, cam->ros_namespace, service,
                                 request_qos);
      if (!server) return server.error();
      pc->server = std::make_unique<Server>(std::move(server).value());
      pc->sources = std::make_unique<dds::WriterSources>(pc->server->request_reader());
      s->servers_.push_back(std::move(pc));
      if (auto l = dds::SetDataAvailableListener(s->servers_.back()->server->request_reader(),
                                                 &RequestServer::OnDataAvailable,
                                                 s->servers_.back().get());
          !l)
        return l.error();
      // A request that came before the listener was set raised no callback.
      s->Receive(*s->servers_.back());
    }
    s->serving_.store(true, std::memory_order_release);  // servers_ is complete
    return s;
  }

  ~RequestServer() {
    // No callback may run into a half-destroyed server: Cyclone's dds_set_listener waits
    // for a running one to return.
    for (auto& pc : servers_) dds::SetDataAvailableListener(pc->server->request_reader());
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
    }
    wake_.notify_all();
    if (thread_.joinable()) thread_.join();
  }
  RequestServer(const RequestServer&) = delete;
  RequestServer& operator=(const RequestServer&) = delete;

 private:
  struct Client {
    uint64_t guid = 0;        // its client id
    int64_t seq = 0;          // its newest request
    std::string client;       // who it belongs to (ClientOf)
    bool changed_id = false;  // a flood of made-up clients: refused as it arrives
    std::chrono::steady_clock::time_point learnt;
  };
  // A client's budget: requests it may still send now.
  struct Budget {
    double tokens = 0;
    std::chrono::steady_clock::time_point refilled, heard;
  };
  struct PerCamera {
    const CameraSetup* camera;
    std::unique_ptr<Server> server;
    RequestServer* owner;
    std::unique_ptr<dds::WriterSources> sources;  // of its requests; under ids_mutex_
  };
  RequestServer() = default;

  // Cyclone's topic filter, on its receive thread as a request arrives, before it is read or
  // takes a place in the reader's history: a known client with no budget left is refused here,
  // at the least cost (a flood's requests, nearly all of them). Admit charges and decides the
  // rest. Runs under the reader's history lock: it must not call into DDS.
  static bool OnArrival(const dds_sample_info_t* info, void* arg) {
    auto* pc = static_cast<PerCamera*>(arg);
    return pc->owner->HasBudget(*pc, info->publication_handle);
  }

  bool HasBudget(const PerCamera& pc, dds_instance_handle_t publication) {
    const auto now = std::chrono::steady_clock::now();
    {
      std::lock_guard<std::mutex> lock(ids_mutex_);
      const auto writer = clients_.find(publication);
      if (writer == clients_.end()) return true;  // not yet known: Admit learns it
      if (writer->second.changed_id) return false;
      const auto budget = budgets_.find(writer->second.client);
      if (budget == budgets_.end()) return true;
      Refill(budget->second, now);
      if (budget->second.tokens >= 1) return true;
    }
    WarnOverRate(pc, now);
    return false;
  }

  // Under ids_mutex_: the tokens a client's budget has earned since it was last refilled.
  void Refill(Budget& b, std::chrono::steady_clock::time_point now) {
    b.tokens = std::min(
        kBurst, b.tokens + ShareNow(now) * std::chrono::duration<double>(now - b.refilled).count());
    b.refilled = now;
  }

  void WarnOverRate(const PerCamera& pc, std::chrono::steady_clock::time_point now) {
    Warn(now, [&] {
      return pc.camera->id + ": a client sends more than its share of requests (" +
             std::to_string(static_cast<int>(kMaxRequestsPerSecond)) +
             " a second, less while many clients ask); the excess is dropped";
    });
  }

  static void OnDataAvailable(dds_entity_t, void* arg) {
    auto* pc = static_cast<PerCamera*>(arg);
    pc->owner->Receive(*pc);
  }

  void Receive(PerCamera& pc) {
    auto taken = pc.server->template TakeRequests<Incoming>(
        [&](const Request& r, const dds::RequestHeader& h) {
          return Incoming{pc.camera, parse_(r), h, pc.server.get(), std::string()};
        });
    if (!taken) {
      std::cerr << "monocled: " << taken.error() << "\n";
      return;
    }
    for (auto& in : std::move(taken).value()) {
      const Admission admitted = Admit(pc, in.header, &in.client);
      if (admitted == Admission::kDrop) continue;
      if (quick_ && quick_(in.value) && in.server->ClientReaderMatched(in.header)) {
        handle_(std::move(in));
        continue;
      }
      std::lock_guard<std::mutex> lock(mutex_);
      Enqueue(pc, std::move(in));
      wake_.notify_one();
    }
  }

  // A request without a client id (the ROS 2 header's guid 0) cannot be told from others'
  // and its reply would reach nobody in particular: dropped. A ROS 2 client keeps one client
  // id for its request writer (rmw_cyclonedds_cpp: the writer's own id; monocle's client
  // too), so a writer whose id changes between requests is not a client but a flood of
  // made-up ones: its requests after the first id are dropped before any work (from then on
  // as they arrive, OnArrival), and no reply (which every client's reply reader would
  // receive and have to discard) is sent. A writer over its client's share of the rate is
  // dropped too. All logged at most once a second. `client` is set to who sent it (ClientOf).
  enum class Admission { kNow, kDrop };
  Admission Admit(PerCamera& pc, const dds::RequestHeader& h, std::string* client) {
    const auto now = std::chrono::steady_clock::now();
    if (h.guid == 0) {
      Warn(now,
           [&] { return pc.camera->id + ": a request without a client id (guid 0) was dropped"; });
      return Admission::kDrop;
    }
    enum { kOk, kChangedId, kOverRate } verdict = kOk;
    {
      std::lock_guard<std::mutex> lock(ids_mutex_);
      // Bounded: a long-running service forgets old writers and learns them again.
      if (clients_.size() > kMaxKnownWriters) clients_.clear();
      if (budgets_.size() > kMaxKnownWriters) budgets_.clear();
      const auto [it, first] =
          clients_.try_emplace(h.publication, Client{h.guid, h.seq, "", false, now});
      Client& c = it->second;
      if (c.client.empty() || c.client.rfind("writer ", 0) == 0) c.client = ClientOf(pc, h);
      *client = c.client;
      if (!first && c.guid != h.guid) {
        verdict = kChangedId;
        c.changed_id = true;
      } else {
        Budget& b = budgets_.try_emplace(*client, Budget{kBurst, now, now}).first->second;
        Refill(b, now);
        b.heard = now;
        if (b.tokens < 1) {
          verdict = kOverRate;
        } else {
          b.tokens -= 1;
          // A client sends a request of an idempotent service (points, poses) again when no
          // reply came (the request or the reply was lost): the newest one is answered again;
          // a copy older than a request already taken is dropped.
          if (!first && h.seq < c.seq) return Admission::kDrop;
          c.seq = h.seq;
          return Admission::kNow;
        }
      }
    }
    if (verdict == kOverRate) {
      WarnOverRate(pc, now);
    } else {
      Warn(now, [&] {
        return pc.camera->id +
               ": a request writer changed its client id (guid) between requests; its requests "
               "under a new id are dropped";
      });
    }
    return Admission::kDrop;
  }

  // Under ids_mutex_: who sent a request, the key of its budget and queue.
  std::string ClientOf(PerCamera& pc, const dds::RequestHeader& h) {
    const std::string& participant = pc.sources->Of(h.publication);
    if (participant.empty()) return "writer " + std::to_string(h.publication);
    return by_identity_ ? "identity " + dds::IdentityOfParticipant(participant) : participant;
  }

  // Under ids_mutex_: each client's rate now, requests a second.
  double ShareNow(std::chrono::steady_clock::time_point now) {
    if (now - share_counted_ > std::chrono::milliseconds(100)) {
      share_counted_ = now;
      size_t active = 0;
      for (const auto& [id, b] : budgets_) active += now - b.heard < std::chrono::seconds(1);
      share_ =
          std::clamp(kServiceRequestsPerSecond / static_cast<double>(std::max<size_t>(active, 1)),
                     kMinRequestsPerSecond, kMaxRequestsPerSecond);
    }
    return share_;
  }

  // Logs at most once a second. `what` is a string or a callable making it: a flood's drops
  // call this for every request, and only a logged message is worth building.
  template <typename What>
  void Warn(std::chrono::steady_clock::time_point now, const What& what) {
    std::lock_guard<std::mutex> lock(warn_mutex_);
    if (now - last_warning_ < std::chrono::seconds(1)) return;
    last_warning_ = now;
    if constexpr (std::is_invocable_v<What>) {
      std::cerr << "monocled: " << what() << "\n";
    } else {
      std::cerr << "monocled: " << what << "\n";
    }
  }

  // Under mutex_.
  void Enqueue(PerCamera& pc, Incoming&& in) {
    const std::string client = in.client;
    auto& mine = queues_[client];
    if (mine.empty()) turns_.push_back(client);
    if (mine.size() >= kMaxQueuedPerClient || queued_ >= kMaxQueued) {
      // Drop from the longest queue (this client's when it is the one filling it).
      auto longest = queues_.begin();
      for (auto it = queues_.begin(); it != queues_.end(); ++it)
        if (it->second.size() > longest->second.size()) longest = it;
      auto& victim = mine.size() >= kMaxQueuedPerClient ? mine : longest->second;
      if (!victim.empty()) {
        victim.pop_front();
        --queued_;
      }
      Warn(std::chrono::steady_clock::now(),
           pc.camera->id + ": too many requests waiting; a client's oldest was dropped");
    }
    mine.push_back(std::move(in));
    ++queued_;
  }

  // Under mutex_: the next request, one client after another.
  bool Dequeue(Incoming* out) {
    while (!turns_.empty()) {
      const std::string client = turns_.front();
      turns_.pop_front();
      auto it = queues_.find(client);
      if (it == queues_.end() || it->second.empty()) {
        if (it != queues_.end()) queues_.erase(it);
        continue;
      }
      *out = std::move(it->second.front());
      it->second.pop_front();
      --queued_;
      if (it->second.empty()) {
        queues_.erase(it);
      } else {
        turns_.push_back(client);
      }
      return true;
    }
    return false;
  }

  void Run() {
    std::unique_lock<std::mutex> lock(mutex_);
    while (!stop_) {
      wake_.wait_for(lock, parked_.empty() ? kTick : kParkedCheck,
                     [&] { return stop_ || queued_ > 0; });
      Incoming in;
      while (!stop_ && Dequeue(&in)) {
        lock.unlock();
        if (in.server->ClientReaderMatched(in.header)) {
          handle_(std::move(in));
        } else {
          Park(std::move(in));
        }
        lock.lock();
      }
      lock.unlock();
      HandleParked();
      lock.lock();
      if (tick_) {
        lock.unlock();
        tick_();
        lock.lock();
      }
      if (const auto now = std::chrono::steady_clock::now();
          serving_.load(std::memory_order_acquire) && now >= next_forget_) {
        next_forget_ = now + kForgetPeriod;
        lock.unlock();
        ForgetDeparted();
        lock.lock();
      }
    }
  }

  // Departed clients' bookkeeping (a few hundred bytes each), forgotten every kForgetPeriod
  // instead of growing until kMaxKnownWriters: their writers are no longer matched, and a
  // budget idle for a second and full again is a new client's. DDS is asked outside
  // ids_mutex_, which OnArrival takes under the reader's history lock.
  void ForgetDeparted() {
    const auto asked = std::chrono::steady_clock::now();
    std::vector<std::vector<dds_instance_handle_t>> matched;
    std::vector<dds_instance_handle_t> all;
    for (auto& pc : servers_) {
      auto handles = dds::MatchedPublications(pc->server->request_reader());
      if (!handles) return;  // DDS cannot say now: forget nothing
      pc->server->ForgetDepartedClients(*handles);
      all.insert(all.end(), handles->begin(), handles->end());
      matched.push_back(std::move(*handles));
    }
    std::sort(all.begin(), all.end());
    std::lock_guard<std::mutex> lock(ids_mutex_);
    // A writer learnt since the question may have matched since: kept until the next sweep.
    dds::EraseUnmatched(clients_, all, [&](const auto& c) { return c.second.learnt >= asked; });
    for (size_t i = 0; i < servers_.size(); ++i) servers_[i]->sources->ForgetUnmatched(matched[i]);
    const auto now = std::chrono::steady_clock::now();
    for (auto it = budgets_.begin(); it != budgets_.end();) {
      Budget& b = it->second;
      const bool idle = now - b.heard >= std::chrono::seconds(1);
      if (idle) Refill(b, now);
      it = idle && b.tokens >= kBurst ? budgets_.erase(it) : std::next(it);
    }
  }

  // Only the server's thread touches parked_.
  void Park(Incoming&& in) {
    if (parked_.size() >= kMaxParked) {
      parked_.pop_front();
      Warn(std::chrono::steady_clock::now(),
           "too many requests from clients not yet discovered; the oldest was dropped");
    }
    parked_.push_back({std::chrono::steady_clock::now(), std::move(in)});
  }

  void HandleParked() {
    const auto now = std::chrono::steady_clock::now();
    for (auto it = parked_.begin(); it != parked_.end();) {
      if (it->second.server->ClientReaderMatched(it->second.header)) {
        Incoming in = std::move(it->second);
        it = parked_.erase(it);
        handle_(std::move(in));
      } else if (now - it->first > kParkedLimit) {
        Warn(now, it->second.camera->id +
                      ": a client's reply reader was never discovered; its request was dropped");
        it = parked_.erase(it);
      } else {
        ++it;
      }
    }
  }

  std::vector<std::unique_ptr<PerCamera>> servers_;
  bool by_identity_ = false;  // clients are identities (DDS Security), not participants
  Parse parse_;
  Handle handle_;
  Quick quick_;
  Tick tick_;
  std::mutex mutex_;
  std::condition_variable wake_;
  std::map<std::string, std::deque<Incoming>> queues_;  // per client (participant)
  std::deque<std::string> turns_;                       // clients waiting, in turn
  size_t queued_ = 0;
  bool stop_ = false;
  std::deque<std::pair<std::chrono::steady_clock::time_point, Incoming>> parked_;
  std::mutex ids_mutex_;
  // Request writer -> its client id and the last sequence number taken from it.
  std::map<dds_instance_handle_t, Client> clients_;      // by request writer
  std::map<std::string, Budget> budgets_;                // by client (ClientOf)
  std::chrono::steady_clock::time_point next_forget_{};  // the server's thread's
  std::atomic<bool> serving_{false};  // Start is done: the server's thread may read servers_
  double share_ = kMaxRequestsPerSecond;
  std::chrono::steady_clock::time_point share_counted_{};
  std::mutex warn_mutex_;
  std::chrono::steady_clock::time_point last_warning_{};
  std::thread thread_;
};

}  // namespace monocle
