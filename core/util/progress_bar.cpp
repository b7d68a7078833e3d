// ProgressBar: rendering of the progress line and the terminal / log drawing policy.
#include "core/util/progress_bar.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <iostream>
#include <sstream>

namespace facetool {
namespace {

constexpr double kTerminalRedrawSeconds = 0.1;
constexpr double kLogLineSeconds = 5.0;

std::string format_rate(double per_second) {
  char text[32];
  if (per_second >= 100)
    std::snprintf(text, sizeof(text), "%.0f", per_second);
  else if (per_second >= 1)
    std::snprintf(text, sizeof(text), "%.1f", per_second);
  else
    std::snprintf(text, sizeof(text), "%.3f", per_second);
  return text;
}

}  // namespace

std::string format_duration(double seconds) {
  const int64_t total = static_cast<int64_t>(std::max(0.0, seconds) + 0.5);
  const int64_t hours = total / 3600, minutes = (total / 60) % 60, secs = total % 60;
  char text[48];
  if (hours > 0)
    std::snprintf(text, sizeof(text), "%lld:%02lld:%02lld", static_cast<long long>(hours),
                  static_cast<long long>(minutes), static_cast<long long>(secs));
  else
    std::snprintf(text, sizeof(text), "%02lld:%02lld", static_cast<long long>(minutes),
                  static_cast<long long>(secs));
  return text;
}

std::string format_progress(const std::string& label, int64_t done, int64_t total,
                            double elapsed_seconds, const std::string& unit, int bar_width) {
  std::ostringstream line;
  if (!label.empty()) line << label << ' ';
  if (total > 0) {
    const double fraction = std::clamp(static_cast<double>(done) / total, 0.0, 1.0);
    const int filled = static_cast<int>(fraction * bar_width);
    line << '[' << std::string(filled, '#') << std::string(bar_width - filled, '.') << "] "
         << done << '/' << total;
  } else {
    line << done;
  }
  const double rate = elapsed_seconds > 0 ? done / elapsed_seconds : 0.0;
  line << ' ' << format_rate(rate) << ' ' << unit << "/s";
  if (total > 0) {
    if (done >= total)
      line << " in " << format_duration(elapsed_seconds);
    else if (rate > 0)
      line << " ETA " << format_duration((total - done) / rate);
    else
      line << " ETA --:--";
  }
  return line.str();
}

ProgressBar::ProgressBar(std::string label, int64_t total, std::string unit)
    : ProgressBar(std::move(label), total, std::move(unit), std::cerr, isatty(STDERR_FILENO)) {}

ProgressBar::ProgressBar(std::string label, int64_t total, std::string unit, std::ostream& out,
                         bool interactive)
    : label_(std::move(label)),
      total_(total),
      unit_(std::move(unit)),
      out_(out),
      interactive_(interactive),
      start_(Clock::now()),
      last_draw_(start_) {
  if (interactive_) draw(false);
}

ProgressBar::~ProgressBar() { finish(); }

double ProgressBar::elapsed_seconds() const {
  return std::chrono::duration<double>(Clock::now() - start_).count();
}

void ProgressBar::update(int64_t done) {
  if (finished_) return;
  done_ = done;
  const double since_draw = std::chrono::duration<double>(Clock::now() - last_draw_).count();
  if (interactive_) {
    if (since_draw >= kTerminalRedrawSeconds) draw(false);
    return;
  }
  const int decile = total_ > 0 ? static_cast<int>(10 * std::min(done_, total_) / total_) : -1;
  if ((decile > last_decile_ || total_ <= 0) && since_draw >= kLogLineSeconds) {
    last_decile_ = decile;
    draw(false);
  }
}

void ProgressBar::finish() {
  if (finished_) return;
  finished_ = true;
  draw(true);
}

void ProgressBar::draw(bool final_line) {
  last_draw_ = Clock::now();
  const std::string line = format_progress(label_, done_, total_, elapsed_seconds(), unit_);
  if (interactive_) {
    // Pad with spaces so a shorter line fully covers the previous one.
    const size_t padding = last_width_ > line.size() ? last_width_ - line.size() : 0;
    out_ << '\r' << line << std::string(padding, ' ');
    last_width_ = line.size();
    if (final_line) out_ << '\n';
  } else {
    out_ << line << '\n';
  }
  out_.flush();
}

}  // namespace facetool
