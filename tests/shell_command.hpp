// Runs a shell command as a user would and collects its standard output and
// exit code: the tests that drive the `mbrt` command line share it.
#pragma once

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>

#include <doctest/doctest.h>

struct CommandRun {
  int exit_code;
  std::string out;
};

inline CommandRun run_shell(const std::string& command) {
  CommandRun r{-1, ""};
  FILE* p = popen(command.c_str(), "r");
  REQUIRE(p != nullptr);
  std::array<char, 4096> buf;
  while (size_t n = fread(buf.data(), 1, buf.size(), p)) r.out.append(buf.data(), n);
  const int status = pclose(p);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}
