// FUZZ_CHECK: a property every fuzz input must keep.
#pragma once

#include <cstdio>
#include <cstdlib>

// A property every input must keep; a failure names itself, then aborts (a fuzzer finding).
#define FUZZ_CHECK(condition)                                                                 \
  do {                                                                                        \
    if (!(condition)) {                                                                       \
      std::fprintf(stderr, "%s:%d: FUZZ_CHECK failed: %s\n", __FILE__, __LINE__, #condition); \
      std::abort();                                                                           \
    }                                                                                         \
  } while (false)
