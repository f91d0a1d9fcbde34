// Files replaced whole: readers see the old file or the new one, never a part; and a write
// that was killed half-way leaves nothing behind for good. The new contents go to an unnamed
// file in the same directory (Linux O_TMPFILE), flushed to disk, given a temporary name
// ".<name>.XXXXXX" only at the end and renamed over the file. Where the file system has no
// unnamed files the temporary is named from the start. While being written it is locked
// (flock); a temporary nobody holds is a killed writer's, removed at the next write.
#pragma once

#include <string>

#include "service/common/result.h"

namespace monocle {

Status WriteFileAtomically(const std::string& path, const std::string& contents);

// Removes the temporaries ".<name of path>.XXXXXX" next to `path` that no writer holds:
// left by a writer that was killed. Returns how many were removed.
int RemoveStaleTemporaries(const std::string& path);

}  // namespace monocle
