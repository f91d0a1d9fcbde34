// Reading a file named by a user without trusting it: only a regular file (not /dev/zero, a
// FIFO or a directory) and only up to a size limit, both checked on the opened descriptor
// before anything is read, so a wrong path costs an error message, never memory or a hang.
#pragma once

#include <cstddef>
#include <functional>
#include <string>

#include "service/common/result.h"

namespace monocle {

// Limits for the files monocle reads; far above any real one.
inline constexpr size_t kMaxTextFileBytes = 4u << 20;     // configuration, calibration, trajectory
inline constexpr size_t kMaxImageFileBytes = 256u << 20;  // one compressed or raw image

// The whole file. `what` names it in errors ("calibration file"). Errors: kNotFound (cannot
// open), kInvalidArgument (not a regular file, or larger than max_bytes), kIo (read failed).
Result<std::string> ReadBoundedFile(const std::string& path, const std::string& what,
                                    size_t max_bytes);

// The same checks, read into the buffer `buffer_of_size(file size)` returns (at least that
// large): a large file is read once, into where it is used, without zeroing or copying it.
// Returns how many bytes were read (fewer if the file shrank meanwhile).
Result<size_t> ReadBoundedFileInto(const std::string& path, const std::string& what,
                                   size_t max_bytes,
                                   const std::function<char*(size_t size)>& buffer_of_size);

}  // namespace monocle
