// Aravis hands each buffer between its stream thread and ours through GLib's queues, which
// ThreadSanitizer cannot see (GLib is not instrumented). Where our own code touches a buffer
// on Aravis's thread (the simulated cameras' fill callback writes the pixels), TSan then saw
// every pixel our thread copies as racing with those writes: each report was suppressed
// (tsan.supp, libaravis), but suppressing a report per racy address cost so much that
// monocled under TSan delivered no frame at all. The hand-off is synchronised (the queues
// lock); these calls tell TSan so. Without ThreadSanitizer they are nothing.
#pragma once

#if defined(MONOCLE_TSAN)
extern "C" void __tsan_acquire(void* addr);
extern "C" void __tsan_release(void* addr);
extern "C" void AnnotateIgnoreReadsBegin(const char* file, int line);
extern "C" void AnnotateIgnoreReadsEnd(const char* file, int line);
#endif

namespace monocle {

// The side that hands the buffer over (after its last access).
inline void BufferHandedOver([[maybe_unused]] const void* buffer) {
#if defined(MONOCLE_TSAN)
  __tsan_release(const_cast<void*>(buffer));
#endif
}

// The side that takes the buffer over (before its first access).
inline void BufferTakenOver([[maybe_unused]] const void* buffer) {
#if defined(MONOCLE_TSAN)
  __tsan_acquire(const_cast<void*>(buffer));
#endif
}

// A received GigE Vision frame is written by Aravis's own stream thread (recvmsg and memcpy
// called from libaravis), and no code of ours runs on that thread to say "handed over": TSan
// saw our copy of every pixel as racing with those writes, and suppressing a report per racy
// address let monocled under TSan deliver one frame in 40 s. Under TSan the frame is copied
// out of the buffer at once with reads ignored for that copy only; without TSan this is
// nothing (the frame stays a zero-copy view).
class IgnoredReadsOfForeignBuffer {
 public:
  IgnoredReadsOfForeignBuffer() {
#if defined(MONOCLE_TSAN)
    AnnotateIgnoreReadsBegin(__FILE__, __LINE__);
#endif
  }
  ~IgnoredReadsOfForeignBuffer() {
#if defined(MONOCLE_TSAN)
    AnnotateIgnoreReadsEnd(__FILE__, __LINE__);
#endif
  }
  IgnoredReadsOfForeignBuffer(const IgnoredReadsOfForeignBuffer&) = delete;
  IgnoredReadsOfForeignBuffer& operator=(const IgnoredReadsOfForeignBuffer&) = delete;
};

// True in a ThreadSanitizer build.
inline constexpr bool kThreadSanitizer =
#if defined(MONOCLE_TSAN)
    true;
#else
    false;
#endif

}  // namespace monocle
