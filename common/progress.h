#pragma once
// A one-line progress bar on stderr, drawn only when stderr is a terminal.

#include <cstdint>
#include <string>

namespace nadir {

class ProgressBar {
 public:
  ProgressBar(std::string label, double total, bool enabled);
  ~ProgressBar();
  void update(double done);
  void finish();

 private:
  std::string label_;
  double total_;
  bool enabled_;
  int64_t last_draw_us_ = 0;
  int64_t start_us_;
  bool finished_ = false;
};

// True when stderr is a terminal (progress bars make sense).
bool stderr_is_terminal();

}  // namespace nadir
