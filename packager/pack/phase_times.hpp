#pragma once
// --time-report: the wall time of each stage of a pack, printed as each ends (statepack's main prints its
// own stages the same way).
#include <chrono>
#include <ostream>
#include <string>

namespace statepack::packager {

class PhaseTimes {
 public:
  explicit PhaseTimes(std::ostream* out) : out_(out) {}
  void done(const std::string& phase) {
    if (!out_) return;
    const auto now = std::chrono::steady_clock::now();
    *out_ << "statepack: time: " << phase << ": "
          << std::chrono::duration<double, std::milli>(now - last_).count() << " ms\n";
    last_ = now;
  }
  void note(const std::string& text) {
    if (out_) *out_ << "statepack: " << text << '\n';
  }

 private:
  std::ostream* out_;
  std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
};

}  // namespace statepack::packager
