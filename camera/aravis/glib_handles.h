// RAII for the GLib handles Aravis hands out: one owner each, destructors never throw.
#pragma once

#include <arv.h>

#include <string>
#include <utility>

namespace monocle {

// Owns one reference to a GObject.
template <typename T>
class GObjectPtr {
 public:
  GObjectPtr() = default;
  explicit GObjectPtr(T* p) : p_(p) {}
  ~GObjectPtr() { reset(); }
  GObjectPtr(GObjectPtr&& o) noexcept : p_(std::exchange(o.p_, nullptr)) {}
  GObjectPtr& operator=(GObjectPtr&& o) noexcept {
    if (this != &o) {
      reset();
      p_ = std::exchange(o.p_, nullptr);
    }
    return *this;
  }
  GObjectPtr(const GObjectPtr&) = delete;
  GObjectPtr& operator=(const GObjectPtr&) = delete;

  T* get() const { return p_; }
  explicit operator bool() const { return p_ != nullptr; }
  void reset() {
    if (p_ != nullptr) g_object_unref(p_);
    p_ = nullptr;
  }

 private:
  T* p_ = nullptr;
};

// Collects a GError for one call and turns it into text.
class GErrorSlot {
 public:
  GErrorSlot() = default;
  ~GErrorSlot() { g_clear_error(&e_); }
  GErrorSlot(const GErrorSlot&) = delete;
  GErrorSlot& operator=(const GErrorSlot&) = delete;

  GError** out() {
    g_clear_error(&e_);
    return &e_;
  }
  bool failed() const { return e_ != nullptr; }
  std::string message() const { return e_ != nullptr ? e_->message : ""; }

 private:
  GError* e_ = nullptr;
};

}  // namespace monocle
