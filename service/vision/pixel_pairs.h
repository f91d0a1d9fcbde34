// The last two of the three loops of a bilinear read of many positions (MeasureEdgeStretch's
// patches, the other-ray check's rings): gather each sample's 2 x 2 neighbours, then blend
// them. Kept as two loops: the gather only moves bytes (each pixel pair as one 16-bit value,
// left | right << 8) and leaves converting them to float to the blend, which vectorizes; one
// loop doing both did not. Inline, so that each caller's loops are compiled with its own.
#pragma once

#include <cstddef>
#include <cstdint>

namespace monocle {

// top_pair[i], bottom_pair[i]: the pixels at data + offset[i] and the one right of it, and
// the two below them.
inline void GatherPixelPairs(const uint8_t* data, size_t stride, const int32_t* offset, int count,
                             uint16_t* top_pair, uint16_t* bottom_pair) {
  // Unrolled: the loop's own count and jump were a third of its instructions.
#pragma GCC unroll 8
  for (int i = 0; i < count; ++i) {
    const uint8_t* r0 = data + offset[i];
    const uint8_t* r1 = r0 + stride;
    top_pair[i] = static_cast<uint16_t>(r0[0] | r0[1] << 8);
    bottom_pair[i] = static_cast<uint16_t>(r1[0] | r1[1] << 8);
  }
}

// out[i]: the pairs blended at fractions fx[i] right and fy[i] down.
inline void BlendPixelPairs(const uint16_t* top_pair, const uint16_t* bottom_pair, const float* fx,
                            const float* fy, int count, float* out) {
  for (int i = 0; i < count; ++i) {
    const float p00 = static_cast<float>(top_pair[i] & 0xff);
    const float p01 = static_cast<float>(top_pair[i] >> 8);
    const float p10 = static_cast<float>(bottom_pair[i] & 0xff);
    const float p11 = static_cast<float>(bottom_pair[i] >> 8);
    const float top = p00 + fx[i] * (p01 - p00);
    const float bottom = p10 + fx[i] * (p11 - p10);
    out[i] = top + fy[i] * (bottom - top);
  }
}

}  // namespace monocle
