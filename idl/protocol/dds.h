// RAII over the Cyclone DDS C API: one owner per dds_entity_t, deleted in the destructor
// (which never throws); return codes turned into the project's Error in one place.
#pragma once

#include <dds/dds.h>

#include <algorithm>
#include <chrono>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "service/common/result.h"

namespace monocle::dds {

struct EndpointQos {
  int history_depth = 1;         // samples kept per instance (keep-last)
  bool transient_local = false;  // late-matching readers still receive kept samples
  // A best-effort reader matches reliable and best-effort writers alike (ROS 2's default and
  // sensor-data QoS); a reliable one only reliable writers.
  bool best_effort = false;
  // The reader keeps only samples `accept(sample, accept_arg)` says yes to, decided on
  // arrival, before they take a place in its history (a Cyclone topic filter).
  bool (*accept)(const void* sample, void* arg) = nullptr;
  // Or decided on who sent it (info->publication_handle, the writer), without the sample
  // being read at all: the cheapest way to refuse a sample.
  bool (*accept_from)(const dds_sample_info_t* info, void* arg) = nullptr;
  void* accept_arg = nullptr;
};

Error DdsError(const std::string& what, dds_return_t rc);

class Entity;
// A participant on `domain`. With `security_dir` (one identity of a keystore made by `monocle
// security init`, client/security/keystore.h) it authenticates, encrypts and is bound by
// that identity's permissions (DDS Security); empty: plain DDS.
// `max_sample_bytes` > 0 (a service): Cyclone drops every sample larger than this, in either
// direction, as its first fragment arrives (Internal/MaxSampleSize), before any memory is
// spent on it; the domain is then created here, with CYCLONEDDS_URI's configuration first.
Result<std::shared_ptr<Entity>> CreateParticipant(dds_domainid_t domain,
                                                  const std::string& security_dir = "",
                                                  size_t max_sample_bytes = 0);
// Whether `dir` holds an identity's six files; the error names the first missing one.
Status CheckSecurityDirectory(const std::string& dir);
// Whether `participant` runs DDS Security (was created with an identity).
bool UsesSecurity(dds_entity_t participant);
// The authenticated identity a participant GUID (hex, as WriterSources gives it) carries
// under DDS Security: its first 6 bytes are a hash of the identity certificate's subject
// name, which the builtin authentication plugin checks in the handshake (DDS Security 1.1,
// 9.3.2.5.2, "adjusted participant GUID"). Every participant of one identity shares it.
inline std::string IdentityOfParticipant(const std::string& participant_guid_hex) {
  return participant_guid_hex.substr(0, 12);
}

class Entity {
 public:
  Entity() = default;
  explicit Entity(dds_entity_t e) : e_(e) {}
  // A participant on a domain it created itself owns that domain too, deleted after it.
  Entity(dds_entity_t e, dds_entity_t owned_domain) : e_(e), domain_(owned_domain) {}
  ~Entity() { Reset(); }
  Entity(Entity&& o) noexcept : e_(std::exchange(o.e_, 0)), domain_(std::exchange(o.domain_, 0)) {}
  Entity& operator=(Entity&& o) noexcept {
    if (this != &o) {
      Reset();
      e_ = std::exchange(o.e_, 0);
      domain_ = std::exchange(o.domain_, 0);
    }
    return *this;
  }
  Entity(const Entity&) = delete;
  Entity& operator=(const Entity&) = delete;
  dds_entity_t get() const { return e_; }

 private:
  void Reset() {
    if (e_ > 0) dds_delete(e_);
    if (domain_ > 0) dds_delete(domain_);
    e_ = domain_ = 0;
  }
  dds_entity_t e_ = 0;
  dds_entity_t domain_ = 0;
};

// A participant with one topic of type T and, as asked, a writer and/or a reader.
template <typename T>
class Endpoint {
 public:
  // With its own participant (simple tools); see the overload below for a shared one.
  static Result<Endpoint> Open(dds_domainid_t domain, const dds_topic_descriptor_t* type,
                               const char* topic_name, bool writer, bool reader,
                               EndpointQos eq = {}) {
    auto participant = CreateParticipant(domain);
    if (!participant) return participant.error();
    return Open(*participant, type, topic_name, writer, reader, eq);
  }

  // On a participant shared with other endpoints (one per process keeps discovery cheap).
  static Result<Endpoint> Open(std::shared_ptr<Entity> participant,
                               const dds_topic_descriptor_t* type, const char* topic_name,
                               bool writer, bool reader, EndpointQos eq = {}) {
    Endpoint ep;
    ep.participant_ = std::move(participant);
    dds_qos_t* qos = dds_create_qos();
    dds_qset_reliability(qos,
                         eq.best_effort ? DDS_RELIABILITY_BEST_EFFORT : DDS_RELIABILITY_RELIABLE,
                         DDS_MSECS(100));
    // A slow subscriber must never stall the publisher: keep only the latest samples.
    dds_qset_history(qos, DDS_HISTORY_KEEP_LAST, eq.history_depth);
    if (eq.transient_local) dds_qset_durability(qos, DDS_DURABILITY_TRANSIENT_LOCAL);
    // The topic with default QoS: several endpoints of one participant share a topic and
    // may differ in history and durability, which belong to each reader and writer.
    const dds_entity_t topic =
        dds_create_topic(ep.participant_->get(), type, topic_name, nullptr, nullptr);
    if (topic < 0) {
      dds_delete_qos(qos);
      return DdsError(std::string("cannot create topic ") + topic_name, topic);
    }
    if (writer) {
      ep.writer_ = Entity(dds_create_writer(ep.participant_->get(), topic, qos, nullptr));
      if (ep.writer_.get() < 0) {
        dds_delete_qos(qos);
        return DdsError("cannot create a DDS writer", ep.writer_.get());
      }
    }
    if (reader) {
      // The topic entity is this endpoint's own (dds_create_topic makes a new one each call),
      // so its filter applies to this reader only.
      if (eq.accept != nullptr || eq.accept_from != nullptr) {
        dds_topic_filter filter{};
        if (eq.accept_from != nullptr) {
          filter.mode = DDS_TOPIC_FILTER_SAMPLEINFO_ARG;
          filter.f.sampleinfo_arg = eq.accept_from;
        } else {
          filter.mode = DDS_TOPIC_FILTER_SAMPLE_ARG;
          filter.f.sample_arg = eq.accept;
        }
        filter.arg = eq.accept_arg;
        if (const dds_return_t rc = dds_set_topic_filter_extended(topic, &filter); rc < 0) {
          dds_delete_qos(qos);
          return DdsError(std::string("cannot filter topic ") + topic_name, rc);
        }
      }
      ep.reader_ = Entity(dds_create_reader(ep.participant_->get(), topic, qos, nullptr));
      if (ep.reader_.get() < 0) {
        dds_delete_qos(qos);
        return DdsError("cannot create a DDS reader", ep.reader_.get());
      }
      // One waitset per reader, made once: creating it per wait costs on every request.
      ep.waitset_ = Entity(dds_create_waitset(ep.participant_->get()));
      const dds_entity_t cond = dds_create_readcondition(ep.reader_.get(), DDS_ANY_STATE);
      if (ep.waitset_.get() < 0 || cond < 0 || dds_waitset_attach(ep.waitset_.get(), cond, 0) < 0) {
        dds_delete_qos(qos);
        return DdsError("cannot create a DDS waitset",
                        ep.waitset_.get() < 0 ? ep.waitset_.get() : cond);
      }
    }
    dds_delete_qos(qos);
    return ep;
  }

  // Waits until some reader matches this endpoint's writer (discovery), up to `timeout`.
  bool WaitForReader(std::chrono::milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < deadline) {
      dds_publication_matched_status_t st{};
      if (dds_get_publication_matched_status(writer_.get(), &st) >= 0 && st.current_count > 0)
        return true;
      dds_sleepfor(DDS_MSECS(5));
    }
    return false;
  }

  // Whether a reader matches this endpoint's writer now (e.g. publish images only then).
  bool HasReaders() const {
    dds_publication_matched_status_t st{};
    return dds_get_publication_matched_status(writer_.get(), &st) >= 0 && st.current_count > 0;
  }

  // Whether this endpoint's reader matches some writer now.
  bool HasWriters() const {
    dds_subscription_matched_status_t st{};
    return dds_get_subscription_matched_status(reader_.get(), &st) >= 0 && st.current_count > 0;
  }

  dds_entity_t reader() const { return reader_.get(); }
  dds_entity_t writer() const { return writer_.get(); }

  // Forgets an instance (e.g. an old reply) so kept history does not grow without bound.
  void Unregister(const T& key_holder) { dds_unregister_instance(writer_.get(), &key_holder); }

  Status Write(const T& sample) {
    const dds_return_t rc = dds_write(writer_.get(), &sample);
    if (rc < 0) return DdsError("cannot publish", rc);
    return Ok{};
  }

  // Waits up to `timeout` for samples (0: takes what is there); returns those taken (valid
  // data only, at most 16). `copy(sample)` or `copy(sample, info)` turns the loaned C sample
  // into the caller's type before the loan is returned.
  template <typename Out, typename Copy>
  Result<std::vector<Out>> Take(std::chrono::milliseconds timeout, Copy copy) {
    std::vector<Out> out;
    if (timeout.count() > 0) {
      const dds_return_t rc = dds_waitset_wait(
          waitset_.get(), nullptr, 0,
          DDS_MSECS(std::chrono::duration_cast<std::chrono::milliseconds>(timeout).count()));
      if (rc < 0) return DdsError("waiting for samples failed", rc);
    }
    constexpr int kMax = 16;
    void* samples[kMax] = {};
    dds_sample_info_t infos[kMax];
    const dds_return_t n = dds_take(reader_.get(), samples, infos, kMax, kMax);
    if (n < 0) return DdsError("cannot take samples", n);
    for (int i = 0; i < n; ++i) {
      if (!infos[i].valid_data) continue;
      const T& sample = *static_cast<const T*>(samples[i]);
      if constexpr (std::is_invocable_v<Copy, const T&, const dds_sample_info_t&>) {
        out.push_back(copy(sample, infos[i]));
      } else {
        out.push_back(copy(sample));
      }
    }
    dds_return_loan(reader_.get(), samples, n);
    return out;
  }

 private:
  // Declared first so it is deleted last (deleting it deletes its children too).
  std::shared_ptr<Entity> participant_;
  Entity writer_, reader_, waitset_;
};

// The publication handles of the writers matched to `reader` now, sorted; nullopt when DDS
// cannot say (then nothing should be forgotten for want of a match).
std::optional<std::vector<dds_instance_handle_t>> MatchedPublications(dds_entity_t reader);

// What a map or set keyed by publication handle keys an entry by.
inline dds_instance_handle_t PublicationOf(dds_instance_handle_t h) { return h; }
template <typename Value>
dds_instance_handle_t PublicationOf(const std::pair<const dds_instance_handle_t, Value>& entry) {
  return entry.first;
}

// Erases the entries of `by_publication` whose writer is not in `matched` (sorted) unless
// `keep(entry)`: a departed client's bookkeeping, which would otherwise stay until its map's
// cap (Cyclone never hands out a publication handle twice).
template <typename Container, typename Keep>
void EraseUnmatched(Container& by_publication, const std::vector<dds_instance_handle_t>& matched,
                    Keep keep) {
  std::erase_if(by_publication, [&](const auto& entry) {
    return !std::binary_search(matched.begin(), matched.end(), PublicationOf(entry)) &&
           !keep(entry);
  });
}

// Which participant wrote a sample a reader took: the participant of the matched writer its
// publication handle names, as 32 hex digits (its GUID), remembered per handle; empty when the
// writer is no longer matched. For one reader; not thread-safe.
class WriterSources {
 public:
  explicit WriterSources(dds_entity_t reader) : reader_(reader) {}
  const std::string& Of(dds_instance_handle_t publication) {
    if (const auto it = known_.find(publication); it != known_.end()) return it->second;
    std::string guid;
    if (dds_builtintopic_endpoint_t* w = dds_get_matched_publication_data(reader_, publication)) {
      static const char kHex[] = "0123456789abcdef";
      for (const uint8_t b : w->participant_key.v) {
        guid += kHex[b >> 4];
        guid += kHex[b & 15];
      }
      dds_builtintopic_free_endpoint(w);
    }
    if (known_.size() > 4096) known_.clear();  // bounded; learnt again when needed
    if (guid.empty()) {
      empty_.clear();
      return empty_;  // not remembered: it may match later
    }
    return known_[publication] = guid;
  }

  // Forgets the writers no longer matched (`matched`: MatchedPublications of the reader).
  void ForgetUnmatched(const std::vector<dds_instance_handle_t>& matched) {
    EraseUnmatched(known_, matched, [](const auto&) { return false; });
  }

 private:
  dds_entity_t reader_;
  std::map<dds_instance_handle_t, std::string> known_;
  std::string empty_;
};

// Calls `on_data(reader, arg)` on Cyclone's receive thread whenever samples arrive at
// `reader`; without `on_data`, removes the listener (waiting for a running call to return).
inline Status SetDataAvailableListener(dds_entity_t reader,
                                       void (*on_data)(dds_entity_t, void*) = nullptr,
                                       void* arg = nullptr) {
  dds_listener_t* listener = on_data != nullptr ? dds_create_listener(arg) : nullptr;
  if (listener != nullptr) dds_lset_data_available(listener, on_data);
  const dds_return_t rc = dds_set_listener(reader, listener);  // copies it
  if (listener != nullptr) dds_delete_listener(listener);
  if (rc < 0) return DdsError("cannot set a listener on a DDS reader", rc);
  return Ok{};
}

// Waits for samples on several readers at once (one thread serving many endpoints).
class WaitSet {
 public:
  static Result<WaitSet> Create(std::shared_ptr<Entity> participant) {
    WaitSet ws;
    ws.participant_ = std::move(participant);
    ws.waitset_ = Entity(dds_create_waitset(ws.participant_->get()));
    if (ws.waitset_.get() < 0) return DdsError("cannot create a DDS waitset", ws.waitset_.get());
    return ws;
  }
  // The read condition belongs to the reader and is deleted with it.
  Status Attach(dds_entity_t reader) {
    const dds_entity_t cond = dds_create_readcondition(reader, DDS_ANY_STATE);
    if (cond < 0) return DdsError("cannot create a read condition", cond);
    const dds_return_t rc = dds_waitset_attach(waitset_.get(), cond, 0);
    if (rc < 0) return DdsError("cannot attach to a waitset", rc);
    return Ok{};
  }
  // Until some attached reader has data, or `timeout`.
  void Wait(std::chrono::milliseconds timeout) {
    dds_waitset_wait(waitset_.get(), nullptr, 0, DDS_MSECS(timeout.count()));
  }

 private:
  std::shared_ptr<Entity> participant_;
  Entity waitset_;
};

}  // namespace monocle::dds
