#pragma once

// Runs the real `pavilion` binary (PAVILION_BINARY) from a test, with stdout
// and stderr captured.
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace pavilion::testing {

inline std::string ReadTextFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// The lines of `text`, without their '\n'.
inline std::vector<std::string> SplitLines(const std::string& text) {
  std::vector<std::string> lines;
  std::stringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

// `s` quoted for /bin/sh.
inline std::string ShellQuote(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

struct PavilionResult {
  int exit_code = -1;  // -1 when the process did not exit normally
  std::string out;
  std::string err;
};

// Runs `pavilion args...` with stdout and stderr captured in files of `dir`.
inline PavilionResult RunPavilion(const std::vector<std::string>& args,
                                  const std::filesystem::path& dir) {
  const std::filesystem::path out = dir / "stdout.txt";
  const std::filesystem::path err = dir / "stderr.txt";
  // Appended piece by piece: GCC 12 warns falsely (-Wrestrict) on chained `+`.
  std::string command = ShellQuote(PAVILION_BINARY);
  for (const std::string& a : args) command.append(" ").append(ShellQuote(a));
  command.append(" >").append(ShellQuote(out.string()));
  command.append(" 2>").append(ShellQuote(err.string()));
  command.append(" </dev/null");
  const int status = std::system(command.c_str());
  PavilionResult r;
  r.exit_code = status != -1 && WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = ReadTextFile(out);
  r.err = ReadTextFile(err);
  return r;
}

}  // namespace pavilion::testing
