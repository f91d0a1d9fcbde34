// Whole processes for the service benchmarks: start one with its output in a log, stop it
// with SIGTERM, and the percentile of a sample.
#pragma once

#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

namespace monocle::bench {

inline double Percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<size_t>(p * static_cast<double>(v.size())))];
}

// Runs `args` (argv[0] searched in PATH) with stdout and stderr in `log`.
inline pid_t Spawn(const std::vector<std::string>& args, const std::string& log) {
  std::cout.flush();  // the child must not print what the parent has buffered
  const pid_t pid = fork();
  if (pid == 0) {
    // A benchmark that dies (or is killed) takes what it started with it.
    prctl(PR_SET_PDEATHSIG, SIGTERM);
    if (freopen(log.c_str(), "w", stdout) == nullptr ||
        freopen(log.c_str(), "a", stderr) == nullptr)
      _exit(126);
    std::vector<char*> argv;
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    execvp(argv[0], argv.data());
    _exit(127);
  }
  return pid;
}

// User + system CPU seconds of `pid` so far (/proc/PID/stat fields 14 and 15).
inline double CpuSeconds(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
  std::string line;
  std::getline(in, line);
  if (line.empty()) return 0;
  std::istringstream fields(line.substr(line.rfind(')') + 2));
  std::string f;
  long utime = 0, stime = 0;
  for (int i = 3; i <= 15 && fields >> f; ++i) {
    if (i == 14) utime = std::stol(f);
    if (i == 15) stime = std::stol(f);
  }
  return static_cast<double>(utime + stime) / static_cast<double>(sysconf(_SC_CLK_TCK));
}

inline void Stop(pid_t pid) {
  kill(pid, SIGTERM);
  waitpid(pid, nullptr, 0);
}

}  // namespace monocle::bench
