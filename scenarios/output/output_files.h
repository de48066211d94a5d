#pragma once

#include <string>

namespace pavilion::scenarios {

// Writes a whole file through a temporary file and a rename, so a reader never
// sees a half-written file and an interrupted run leaves the previous version.
// Creates missing parent folders. Throws std::runtime_error naming the file.
void WriteFileAtomically(const std::string& path, const std::string& contents);

// Appends lines to a file as a run goes (events.jsonl, trajectories.csv). Each
// Flush() makes the lines written so far durable as complete lines.
class LineWriter {
 public:
  explicit LineWriter(std::string path);
  ~LineWriter();
  LineWriter(const LineWriter&) = delete;
  LineWriter& operator=(const LineWriter&) = delete;

  void Append(const std::string& line);  // adds '\n'
  void Flush();

 private:
  std::string path_;
  std::string buffer_;
  int fd_ = -1;
};

// Peak resident set size of this process (MB), from getrusage.
double PeakRssMb();

}  // namespace pavilion::scenarios
