// ProgressBar: a one-line progress display on stderr for long loops (label, bar, rate, ETA).
#pragma once

#include <chrono>
#include <cstdint>
#include <iosfwd>
#include <string>

namespace facetool {

// Renders one progress line, e.g. "train [#####.....] 50/100 12.5 it/s ETA 00:04".
// `total` <= 0 means unknown: no bar and no ETA. `bar_width` is the number of bar cells.
std::string format_progress(const std::string& label, int64_t done, int64_t total,
                            double elapsed_seconds, const std::string& unit = "it",
                            int bar_width = 30);

// Formats a duration as "mm:ss", or "h:mm:ss" from one hour on.
std::string format_duration(double seconds);

// Shows progress on stderr. On a terminal it redraws one line in place (at most ~10 times a
// second); otherwise (logs, pipes) it prints a full line at every 10% step, at most every
// few seconds, so logs stay short. The final state is always printed by finish().
class ProgressBar {
 public:
  ProgressBar(std::string label, int64_t total, std::string unit = "it");
  // For tests and redirection: writes to `out` and treats it as a terminal iff `interactive`.
  ProgressBar(std::string label, int64_t total, std::string unit, std::ostream& out,
              bool interactive);
  ~ProgressBar();  // calls finish() if it was not called
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;

  void advance(int64_t steps = 1) { update(done_ + steps); }
  void update(int64_t done);
  // Prints the final state and ends the line; further calls do nothing.
  void finish();

 private:
  using Clock = std::chrono::steady_clock;
  double elapsed_seconds() const;
  void draw(bool final_line);

  std::string label_;
  int64_t total_;
  std::string unit_;
  std::ostream& out_;
  bool interactive_;
  int64_t done_ = 0;
  bool finished_ = false;
  Clock::time_point start_;
  Clock::time_point last_draw_;
  int last_decile_ = -1;
  size_t last_width_ = 0;
};

}  // namespace facetool
