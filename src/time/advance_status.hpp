// SPDX-License-Identifier: MIT
#pragma once
/// @file How one call to a stepper's advance() ended: the dynamic Stepper and the static
/// LoadStepper answer in the same four words.

namespace slidebeam {

enum class AdvanceStatus {
  Accepted,  ///< a step was taken
  Cut,       ///< it failed; the next call tries a shorter one (the state is at the last step)
  Failed,    ///< it failed at the shortest step allowed (the state is at the last step)
  Event,     ///< an event indicator crossed during the step
};

inline const char* to_string(AdvanceStatus s) {
  switch (s) {
    case AdvanceStatus::Accepted: return "accepted";
    case AdvanceStatus::Cut: return "cut";
    case AdvanceStatus::Failed: return "failed";
    case AdvanceStatus::Event: return "event";
  }
  return "event";
}

}  // namespace slidebeam
