// SPDX-License-Identifier: MIT
#pragma once
/// @file The model's event indicators in one list: every EventSource effect's g_i(x), with the
/// scale each is judged against. The dynamic Stepper locates crossings on the step size; the
/// LoadStepper rejects a load step whose state has crossed. Both read them here.

#include "model/effect_parts.hpp"
#include "model/model.hpp"

#include <vector>

namespace slidebeam {

/// One indicator: the effect (model index), its indicator's index there, its scale.
struct EventIndicator {
  int effect = -1;
  int index = 0;
  double scale = 1.0;
};

class EventSet {
 public:
  /// An indicator below this fraction of its scale has crossed (roundoff of s near the end has not).
  static constexpr double kCrossed = 1e-12;

  explicit EventSet(const Model& model);
  bool empty() const { return indicators_.empty(); }
  size_t size() const { return indicators_.size(); }
  const std::vector<EventIndicator>& indicators() const { return indicators_; }
  /// Every indicator at x, summed over the ranks. Collective.
  std::vector<double> values(Vec x) const;
  /// The first indicator of g that has crossed, or -1.
  int first_crossed(const std::vector<double>& g) const;

 private:
  struct Source {
    const EventSource* source;
    size_t first;  // its first indicator's place in indicators_
  };
  const Model& model_;
  std::vector<EventIndicator> indicators_;
  std::vector<Source> sources_;
};

}  // namespace slidebeam
