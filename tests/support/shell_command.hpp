#pragma once
// Runs a shell command (the CLI, h5dump, mpirun) for the tests that check a program's exit code
// and what it prints: stdout and stderr together, as a user sees them.
#include <sys/wait.h>

#include <cstdio>
#include <string>

namespace millsim::testing {

struct ShellResult {
  int code;  // the exit status, -1 when the command could not start or did not exit normally
  std::string output;
};

inline ShellResult runShell(const std::string& cmd) {
  ShellResult r{-1, ""};
  FILE* p = ::popen((cmd + " 2>&1").c_str(), "r");
  if (!p) return r;
  char buf[4096];
  for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, p)) > 0;) r.output.append(buf, n);
  const int status = ::pclose(p);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

}  // namespace millsim::testing
