// ROS 2 services on plain Cyclone DDS, as rmw_cyclonedds_cpp puts them on the wire: a request
// topic rq/<name>Request and a reply topic rr/<name>Reply, every sample beginning with the
// header `uint64 guid; int64 seq`. A client sets guid to its request writer's instance handle
// and seq to a number of its own; the server echoes both; a client drops every reply whose
// guid is not its own (replies to all clients travel on the one reply topic).
#pragma once

#include <algorithm>
#include <atomic>
#include <chrono>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "idl/protocol/dds.h"
#include "idl/protocol/wire.h"

namespace monocle::dds {

struct RequestHeader {
  uint64_t guid = 0;
  int64_t seq = 0;
  dds_instance_handle_t publication = 0;  // the client's request writer, as seen here
};

// One service of the server side: reads requests, writes replies.
template <typename Request, typename Reply>
class ServiceServer {
 public:
  static Result<ServiceServer> Open(const std::shared_ptr<Entity>& participant,
                                    const dds_topic_descriptor_t* request_type,
                                    const dds_topic_descriptor_t* reply_type, const std::string& ns,
                                    const std::string& service,
                                    EndpointQos request_qos = wire::kRequestReaderQos) {
    auto requests =
        Endpoint<Request>::Open(participant, request_type, wire::RequestTopic(ns, service).c_str(),
                                false, true, request_qos);
    if (!requests) return requests.error();
    auto replies =
        Endpoint<Reply>::Open(participant, reply_type, wire::ReplyTopic(ns, service).c_str(), true,
                              false, wire::kReplyWriterQos);
    if (!replies) return replies.error();
    return ServiceServer(std::move(requests).value(), std::move(replies).value());
  }

  dds_entity_t request_reader() const { return requests_.reader(); }

  // The requests waiting now; `copy(request, header)` makes the caller's value of each.
  template <typename Out, typename Copy>
  Result<std::vector<Out>> TakeRequests(Copy copy) {
    std::vector<Out> all;
    for (;;) {
      auto taken = requests_.template Take<Out>(
          std::chrono::milliseconds(0), [&](const Request& r, const dds_sample_info_t& info) {
            return copy(r, RequestHeader{r.guid, r.seq, info.publication_handle});
          });
      if (!taken) return taken.error();
      if (taken->empty()) return all;
      for (auto& t : *taken) all.push_back(std::move(t));
    }
  }

  // Echoes the request's header into `reply` and sends it. A volatile reply reaches only
  // readers matched when it is written, so first wait (briefly) until the reply reader of the
  // requesting client's participant is matched: discovery runs both ways independently, and a
  // client may ask as soon as it sees our request reader.
  Status SendReply(Reply& reply, const RequestHeader& header) {
    reply.guid = header.guid;
    reply.seq = header.seq;
    WaitForClientReader(header.publication, std::chrono::milliseconds(500));
    return replies_.Write(reply);
  }

  // Whether a reply to this client reaches it now, without waiting (a reply that would have
  // to wait for discovery must not be sent from Cyclone's receive thread, which discovery
  // itself needs).
  bool ClientReaderMatched(const RequestHeader& header) {
    return WaitForClientReader(header.publication, std::chrono::milliseconds(0));
  }

  // Forgets the request writers no longer matched (`matched`: MatchedPublications of
  // request_reader()). One matched since is merely looked up again at its next request.
  void ForgetDepartedClients(const std::vector<dds_instance_handle_t>& matched) {
    std::lock_guard<std::mutex> lock(*mutex_);
    EraseUnmatched(matched_clients_, matched, [](dds_instance_handle_t) { return false; });
  }

 private:
  ServiceServer(Endpoint<Request> requests, Endpoint<Reply> replies)
      : requests_(std::move(requests)), replies_(std::move(replies)) {}

  bool WaitForClientReader(dds_instance_handle_t publication, std::chrono::milliseconds limit) {
    {
      // Once a client's reader was seen matched it stays so: later requests cost no lookup.
      std::lock_guard<std::mutex> lock(*mutex_);
      if (matched_clients_.count(publication) != 0) return true;
    }
    dds_builtintopic_endpoint_t* writer =
        dds_get_matched_publication_data(requests_.reader(), publication);
    if (writer == nullptr) return false;  // the client is gone: nothing to wait for
    const dds_guid_t client = writer->participant_key;
    dds_builtintopic_free_endpoint(writer);
    const auto deadline = std::chrono::steady_clock::now() + limit;
    for (;;) {
      dds_instance_handle_t handles[64];
      const dds_return_t n = dds_get_matched_subscriptions(replies_.writer(), handles, 64);
      for (dds_return_t i = 0; i < std::min<dds_return_t>(n, 64); ++i) {
        dds_builtintopic_endpoint_t* reader =
            dds_get_matched_subscription_data(replies_.writer(), handles[i]);
        if (reader == nullptr) continue;
        const bool same = std::equal(std::begin(reader->participant_key.v),
                                     std::end(reader->participant_key.v), std::begin(client.v));
        dds_builtintopic_free_endpoint(reader);
        if (same) {
          std::lock_guard<std::mutex> lock(*mutex_);
          // Bounded: a long-running service forgets old clients and looks them up again.
          if (matched_clients_.size() > 4096) matched_clients_.clear();
          matched_clients_.insert(publication);
          return true;
        }
      }
      if (std::chrono::steady_clock::now() >= deadline) return false;
      dds_sleepfor(DDS_MSECS(1));
    }
  }

  Endpoint<Request> requests_;
  Endpoint<Reply> replies_;
  std::unique_ptr<std::mutex> mutex_ = std::make_unique<std::mutex>();  // movable
  std::set<dds_instance_handle_t> matched_clients_;
};

// One service of the client side. Not thread-safe: one call at a time.
template <typename Request, typename Reply>
class ServiceClient {
 public:
  static Result<ServiceClient> Open(const std::shared_ptr<Entity>& participant,
                                    const dds_topic_descriptor_t* request_type,
                                    const dds_topic_descriptor_t* reply_type, const std::string& ns,
                                    const std::string& service) {
    // Every client of a service reads every reply on its reply topic (the ROS 2 wire): with
    // many clients, others' replies would push ours out of a keep-last history before we
    // take it. The reader keeps only replies to our client id (known once the request writer
    // exists; until then, none: nothing was asked). The reply reader is made first, so it
    // exists before any request can be answered.
    auto guid = std::make_unique<std::atomic<uint64_t>>(0);
    dds::EndpointQos reply_qos = wire::kRosDefaultQos;
    reply_qos.accept = &ServiceClient::IsOurs;
    reply_qos.accept_arg = guid.get();
    auto replies = Endpoint<Reply>::Open(
        participant, reply_type, wire::ReplyTopic(ns, service).c_str(), false, true, reply_qos);
    if (!replies) return replies.error();
    auto requests =
        Endpoint<Request>::Open(participant, request_type, wire::RequestTopic(ns, service).c_str(),
                                true, false, wire::kRosDefaultQos);
    if (!requests) return requests.error();
    dds_instance_handle_t handle = 0;
    if (const dds_return_t rc = dds_get_instance_handle(requests->writer(), &handle); rc < 0)
      return DdsError("cannot read the request writer's handle", rc);
    guid->store(handle);
    return ServiceClient(std::move(requests).value(), std::move(replies).value(), std::move(guid));
  }

  // Both directions matched: a request now reaches the server and its reply reaches us.
  bool WaitForService(std::chrono::milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (!(requests_.HasReaders() && replies_.HasWriters())) {
      if (std::chrono::steady_clock::now() >= deadline) return false;
      dds_sleepfor(DDS_MSECS(2));
    }
    return true;
  }

  uint64_t guid() const { return guid_->load(); }

  // Takes replies only from this participant (dds::WriterSources; empty: from any).
  void TrustOnly(std::string participant) { trusted_ = std::move(participant); }
  // Replies to our requests (this one or an earlier one) from another participant, dropped, so
  // far.
  uint64_t foreign_replies() const { return foreign_replies_; }

  // Sends `request` (its header is set here) and waits up to `timeout` for its reply, which
  // `convert(reply)` turns into the result; nullopt if none came. Replies to other clients,
  // and late replies to our earlier requests, are dropped.
  //
  // With `resend_after` > 0 (idempotent services only: answering twice must do no harm), a
  // request without a reply by then is sent again (same sequence number), then at doubling
  // intervals: a server that has not yet discovered our request writer drops what it sends
  // (DDS delivers nothing from an unknown writer, and a volatile reader that matches later
  // does not get earlier samples), and a reply can be lost to a slow reader.
  template <typename Out, typename Convert>
  Result<std::optional<Out>> Call(Request& request, std::chrono::milliseconds timeout,
                                  Convert convert, std::chrono::milliseconds resend_after) {
    const bool resend = resend_after.count() > 0;
    request.guid = guid();
    request.seq = ++seq_;
    if (auto w = requests_.Write(request); !w) return w.error();
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    auto resend_at = std::chrono::steady_clock::now() + resend_after;
    for (;;) {
      const auto now = std::chrono::steady_clock::now();
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - now);
      if (left.count() <= 0) return std::optional<Out>();
      if (resend && now >= resend_at) {
        if (auto w = requests_.Write(request); !w) return w.error();
        resend_after *= 2;
        resend_at = now + resend_after;
      }
      const auto until_resend =
          std::chrono::duration_cast<std::chrono::milliseconds>(resend_at - now) +
          std::chrono::milliseconds(1);
      auto taken = replies_.template Take<std::optional<Out>>(
          std::min({left, until_resend, std::chrono::milliseconds(100)}),
          [&](const Reply& r, const dds_sample_info_t& info) -> std::optional<Out> {
            if (r.guid != guid()) return std::nullopt;
            // Counted whichever request it answers: a foreign reply that comes after the
            // service's is as much a spoof as one that comes first.
            if (!trusted_.empty() && sources_->Of(info.publication_handle) != trusted_) {
              ++foreign_replies_;
              return std::nullopt;
            }
            if (r.seq != request.seq) return std::nullopt;
            return convert(r);
          });
      if (!taken) return taken.error();
      for (auto& reply : *taken) {
        if (reply) return std::optional<Out>(std::move(*reply));
      }
    }
  }

 private:
  ServiceClient(Endpoint<Request> requests, Endpoint<Reply> replies,
                std::unique_ptr<std::atomic<uint64_t>> guid)
      : guid_(std::move(guid)),
        requests_(std::move(requests)),
        replies_(std::move(replies)),
        sources_(std::make_unique<WriterSources>(replies_.reader())) {}

  // The reply reader's filter (Cyclone's receive thread) reads our client id.
  static bool IsOurs(const void* reply, void* guid) {
    return static_cast<const Reply*>(reply)->guid ==
           static_cast<const std::atomic<uint64_t>*>(guid)->load(std::memory_order_relaxed);
  }

  // First: the reply reader's filter uses it until the reader is gone.
  std::unique_ptr<std::atomic<uint64_t>> guid_;
  Endpoint<Request> requests_;
  Endpoint<Reply> replies_;
  std::unique_ptr<WriterSources> sources_;  // of the replies
  std::string trusted_;
  uint64_t foreign_replies_ = 0;
  int64_t seq_ = 0;
};

}  // namespace monocle::dds
