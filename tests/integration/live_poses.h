// `monocle corner locate --camera ID --json` against a running monocled, as a user runs it,
// and the poses it printed, parsed.
#pragma once

#include <google/protobuf/util/json_util.h>
#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

#include "idl/cli_output.pb.h"
#include "tests/integration/cli_process.h"

namespace monocle::testing {

// `count` poses of camera `camera` on DDS domain `domain` (30 s to come). A failed run or a
// line that is not a pose fails the calling test; what was read is returned.
inline std::vector<proto::LivePoseOutput> ReadLivePoses(const TempDir& dir,
                                                        const std::string& camera, int count,
                                                        int domain) {
  const ProcessResult r =
      RunMonocle(dir, "corner locate --camera " + camera + " --count " + std::to_string(count) +
                          " --json --timeout 30 --domain " + std::to_string(domain));
  EXPECT_EQ(r.exit_code, 0) << r.err << ReadFile(dir / "monocled.log");
  std::vector<proto::LivePoseOutput> poses;
  std::stringstream lines(r.out);
  for (std::string line; std::getline(lines, line);) {
    proto::LivePoseOutput pose;
    if (!google::protobuf::util::JsonStringToMessage(line, &pose).ok()) {
      ADD_FAILURE() << "not a pose: " << line;
      continue;
    }
    poses.push_back(std::move(pose));
  }
  return poses;
}

}  // namespace monocle::testing
