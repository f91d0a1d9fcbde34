// Whole processes for the service benchmarks: start one with its output in a log, stop it
// with SIGTERM, and the percentile of a sample.
#pragma once

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <iostream>
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

inline void Stop(pid_t pid) {
  kill(pid, SIGTERM);
  waitpid(pid, nullptr, 0);
}

}  // namespace monocle::bench
