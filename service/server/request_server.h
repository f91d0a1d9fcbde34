// Serves one kind of request (one ROS 2 service name) for a set of cameras on one thread:
// opens <camera namespace>/<service> for each, waits on all of them at once, copies each
// request out of its sample and hands it to the handler with the camera it was sent to.
// Each handler (point queries, pose queries, floor calibration) owns one of these.
#pragma once

#include <atomic>
#include <chrono>
#include <functional>
#include <iostream>
#include <memory>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "client/protocol/service_endpoints.h"
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

template <typename Request, typename Reply, typename Value>
class RequestServer {
 public:
  using Server = dds::ServiceServer<Request, Reply>;
  struct Incoming {
    const CameraSetup* camera = nullptr;
    Value value;
    dds::RequestHeader header;
    Server* server = nullptr;  // to reply on
  };
  using Parse = std::function<Value(const Request&)>;
  using Handle = std::function<void(Incoming&&)>;
  using Tick = std::function<void()>;  // after every wake (at least every kTick)

  static constexpr std::chrono::milliseconds kTick{100};

  // `cameras` must outlive the server.
  static Result<std::unique_ptr<RequestServer>> Start(
      const std::shared_ptr<dds::Entity>& participant,
      const std::vector<const CameraSetup*>& cameras, const dds_topic_descriptor_t* request_type,
      const dds_topic_descriptor_t* reply_type, const std::string& service, Parse parse,
      Handle handle, Tick tick = nullptr) {
    std::unique_ptr<RequestServer> s(new RequestServer());
    auto waitset = dds::WaitSet::Create(participant);
    if (!waitset) return waitset.error();
    s->waitset_ = std::make_unique<dds::WaitSet>(std::move(waitset).value());
    for (const CameraSetup* cam : cameras) {
      auto server =
          Server::Open(participant, request_type, reply_type, cam->ros_namespace, service);
      if (!server) return server.error();
      s->servers_.push_back({cam, std::make_unique<Server>(std::move(server).value())});
      if (auto a = s->waitset_->Attach(s->servers_.back().server->request_reader()); !a)
        return a.error();
    }
    s->parse_ = std::move(parse);
    s->handle_ = std::move(handle);
    s->tick_ = std::move(tick);
    s->thread_ = std::thread([self = s.get()] { self->Run(); });
    return s;
  }

  ~RequestServer() {
    stop_ = true;
    if (thread_.joinable()) thread_.join();
  }
  RequestServer(const RequestServer&) = delete;
  RequestServer& operator=(const RequestServer&) = delete;

 private:
  struct PerCamera {
    const CameraSetup* camera;
    std::unique_ptr<Server> server;
  };
  RequestServer() = default;

  void Run() {
    while (!stop_) {
      waitset_->Wait(kTick);
      for (auto& pc : servers_) {
        auto taken = pc.server->template TakeRequests<Incoming>(
            [&](const Request& r, const dds::RequestHeader& h) {
              return Incoming{pc.camera, parse_(r), h, pc.server.get()};
            });
        if (!taken) {
          std::cerr << "monocled: " << taken.error() << "\n";
          continue;
        }
        for (auto& in : std::move(taken).value()) handle_(std::move(in));
      }
      if (tick_) tick_();
    }
  }

  std::unique_ptr<dds::WaitSet> waitset_;
  std::vector<PerCamera> servers_;
  Parse parse_;
  Handle handle_;
  Tick tick_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace monocle
