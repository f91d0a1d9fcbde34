// One serialized sample (as DDS carries it and MCAP recordings store it: the 4-byte
// encapsulation header, then the XCDR1 body) decoded into its C type the way Cyclone DDS
// decodes a received sample: dds_stream_normalize_data checks every length and terminator
// first (and byte-swaps big-endian data), then dds_stream_read builds the sample. Recordings
// are files from anywhere: nothing is trusted.
#pragma once

#include <dds/dds.h>
#include <dds/ddsi/ddsi_cdrstream.h>
#include <dds/ddsi/q_protocol.h>

#include <cstdint>
#include <cstring>
#include <memory>
#include <string>
#include <string_view>

namespace monocle::dds {

template <typename Sample>
class DecodedSample {
 public:
  // nullptr if `cdr` is not a well-formed XCDR1 sample of `type`.
  static std::unique_ptr<DecodedSample> Decode(const dds_topic_descriptor_t* type,
                                               std::string_view cdr) {
    // Header: representation id (big-endian 16 bits: 0x0000 CDR_BE, 0x0001 CDR_LE), options.
    constexpr size_t kHeader = 4;
    if (cdr.size() < kHeader || cdr.size() > (1u << 30) || cdr[0] != 0 ||
        (cdr[1] != 0 && cdr[1] != 1)) {
      return nullptr;
    }
    const bool big_endian = cdr[1] == 0;
    std::string body(cdr.substr(kHeader));
    uint32_t end = 0;
    const auto size = static_cast<uint32_t>(body.size());
    if (dds_stream_normalize_data(body.data(), &end, size, big_endian, CDR_ENC_VERSION_1,
                                  type->m_ops) == nullptr) {
      return nullptr;
    }
    std::unique_ptr<DecodedSample> out(new DecodedSample(type));
    dds_istream_t is;
    dds_istream_init(&is, size, body.data(), CDR_ENC_VERSION_1);
    dds_stream_read(&is, reinterpret_cast<char*>(&out->sample_), type->m_ops);
    dds_istream_fini(&is);
    out->filled_ = true;
    return out;
  }
  ~DecodedSample() {
    if (filled_) dds_stream_free_sample(&sample_, type_->m_ops);
  }
  DecodedSample(const DecodedSample&) = delete;
  DecodedSample& operator=(const DecodedSample&) = delete;
  const Sample& get() const { return sample_; }

 private:
  explicit DecodedSample(const dds_topic_descriptor_t* type) : type_(type) {
    std::memset(&sample_, 0, sizeof sample_);
  }
  const dds_topic_descriptor_t* type_;
  Sample sample_;
  bool filled_ = false;
};

}  // namespace monocle::dds
