// Publishes replies of a request/reply pair. Replies are transient-local so a client whose
// reader matched after the reply was written still gets it; the last kKeptReplies are kept
// and older ones unregistered, so the kept history stays bounded.
#pragma once

#include <deque>
#include <mutex>
#include <string>
#include <utility>

#include "service/server/dds.h"

namespace monocle::dds {

inline constexpr size_t kKeptReplies = 64;
inline constexpr EndpointQos kReplyQos{1, true};
inline constexpr EndpointQos kRequestQos{64, false};

// `Reply` is an idlc-generated type keyed by `client_id` and `request_id`.
template <typename Reply>
class ReplyPublisher {
 public:
  explicit ReplyPublisher(Endpoint<Reply> endpoint) : endpoint_(std::move(endpoint)) {}

  Status Publish(const Reply& reply) {
    std::lock_guard<std::mutex> lock(mutex_);
    auto written = endpoint_.Write(reply);
    answered_.emplace_back(reply.client_id != nullptr ? reply.client_id : "", reply.request_id);
    if (answered_.size() > kKeptReplies) {
      Reply key{};
      key.client_id = answered_.front().first.data();
      key.request_id = answered_.front().second;
      endpoint_.Unregister(key);
      answered_.pop_front();
    }
    return written;
  }

 private:
  std::mutex mutex_;
  Endpoint<Reply> endpoint_;
  std::deque<std::pair<std::string, unsigned long long>> answered_;
};

}  // namespace monocle::dds
