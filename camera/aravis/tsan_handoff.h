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

}  // namespace monocle
