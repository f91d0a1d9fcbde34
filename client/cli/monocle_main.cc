// The monocle command line. Offline forms work on images and calibration files; the
// --camera forms and `status` ask the running service over DDS (monocle::Client).
#include <malloc.h>

#include "client/cli/command_table.h"

int main(int argc, char** argv) {
  // Per-image buffers of a megabyte or more would otherwise be mmap'ed and unmapped for
  // every image, paying page faults each time (a fifth of `corner locate`'s time over many
  // files); keep them in the heap for reuse instead.
  mallopt(M_MMAP_THRESHOLD, 64 << 20);
  mallopt(M_TRIM_THRESHOLD, 256 << 20);
  return monocle::cli::RunCommand({argv + 1, argv + argc});
}
