// SPDX-License-Identifier: MIT
/// @file A driven slider (scene table [[slider_drive]]): a haul rope pulling a carriage along its
/// track rope, or a winch. The sliding joint's coordinate s (the slider point's arc length along
/// its carrier) follows a prescribed travel: s(t) = s_0 + the integral of a speed profile that
/// rises linearly from 0 at `start` to `speed` within `ramp` seconds, holds, and falls back to 0
/// within `ramp` seconds so that it is 0 again at `stop`; or s(t) = s_0 + `distance` f(t) with any
/// time function f that starts at 0 (a smooth ramp, a table of a recorded travel, a sine). One
/// multiplier enforces s = s(t) at the end of each step: it is the drive force along the carrier,
/// and its work over the step, -lambda ds, is counted as driving work (W; `<label>.work`).
///
/// Or a force: `force` = F (N) times a time function f(t) (1 without one) along the track, between
/// slider and carrier (a self-propelled trolley, a winch on the carriage; at a guide, a drive
/// wheel pulling the rope through it): the term -F f(t) in the equation of s, so that the joint's
/// force along the carrier's tangent is F f(t). It does the work F f(t) ds over a step, exactly
/// under energy-momentum (f at the step's force time), and depends on time alone: no Jacobian.

#include "effects/common.hpp"
#include "model/time_function.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>

namespace slidebeam::effects {

namespace {
/// Travel of the trapezoidal speed profile: 0 before start, rising to v within a, holding, and
/// falling back to 0 within a so that it is 0 again at stop (a = 0: jumps). Total v (stop - start - a).
double trapezoid_travel(double t, double v, double start, double stop, double a) {
  auto ramp_area = [&](double tau) {  // integral of min(tau', a) / a over [0, tau]: the rising part
    if (tau <= 0.0) return 0.0;
    if (a <= 0.0) return tau;
    return tau < a ? 0.5 * tau * tau / a : tau - 0.5 * a;
  };
  // speed(t) = v (r(t - start) - r(t - stop + a)) with r the unit ramp of length a: its integral
  return v * (ramp_area(t - start) - ramp_area(t - stop + a));
}
}  // namespace

class SliderDrive final : public Effect, public ExtraUnknowns, public PrescribedMotion, public SlidingJointLink {
 public:
  SliderDrive(const Model& m, const EffectParams& p)
      : SlidingJointLink(m, p, "slider_drive"),
        start_(p.number("start", 0.0)),
        stop_(p.number("stop", std::numeric_limits<double>::infinity())),
        ramp_(p.number("ramp", 0.0)),
        by_distance_(p.num.count("distance") > 0) {
    const bool by_speed = p.num.count("speed") > 0;
    if (by_speed == by_distance_)
      throw ParamError(by_speed ? "distance" : "speed",
                       "give either a `speed` (with start, stop, ramp) or a `distance` with a `time_function`");
    if (by_distance_) {
      distance_ = p.number("distance");
      if (p.string("tf_type", "").empty())
        throw ParamError("time_function", "a `distance` travels by a time function: s = s0 + distance f(t)");
      f_ = TimeFunction::from(p);
      if (f_(0.0) != 0.0)
        throw ParamError("time_function", "the travel must start where the slider is drawn: f(0) = " +
                                              format_number(f_(0.0)) + ", not 0");
      return;
    }
    if (!p.string("tf_type", "").empty())
      throw ParamError("time_function", "a time function goes with a `distance` (a `speed` has start, stop and ramp)");
    speed_ = p.number("speed");
    if (!(stop_ > start_)) throw std::invalid_argument("slider_drive: stop must come after start");
    if (ramp_ > 0.5 * (stop_ - start_)) throw std::invalid_argument("slider_drive: the ramps are longer than the travel");
  }
  std::string type() const override { return "slider_drive"; }
  std::string label() const override { return label_; }
  PetscInt n_extra() const override { return 1; }
  bool time_dependent() const override { return true; }

  void distribute(const Model& m) override {
    label_ = link_label(m);
    std::vector<PetscInt> rows;
    std::vector<PetscScalar> vals;
    joint_->joint_unknowns().initial_values(m, rows, vals);  // the slider's s at the start: the travel's origin
    if (!vals.empty()) s0_ = vals[0];
    const PetscInt s = s_index();
    owned_ = s >= m.dof_map().owned_lo() && s < m.dof_map().owned_hi();
  }
  PetscInt elimination_anchor(const Model& m) const override {
    // with the joint's own extras: the multiplier sits next to the s it prescribes
    return joint_anchor(m);
  }
  void needed_dofs(const Model&, std::vector<PetscInt>& dofs) const override {
    if (!owned_) return;
    dofs.push_back(s_index());
    dofs.push_back(extra_offset());
  }
  void initial_values(const Model&, std::vector<PetscInt>&, std::vector<PetscScalar>&) const override {}
  void constrained_state(std::vector<PetscInt>& rows) const override { rows.push_back(s_index()); }
  PetscErrorCode pattern(const Model&, const MatSink& sink) const override {
    PetscFunctionBeginUser;
    if (owned_) {
      const PetscInt d[2] = {s_index(), extra_offset()};
      const double zero[4] = {0, 0, 0, 0};
      PetscCall(sink.add(2, d, 2, d, zero));
    }
    PetscFunctionReturn(0);
  }
  PetscErrorCode residual(const EvalContext& ctx, const LocalValues& r) const override {
    PetscFunctionBeginUser;
    if (!owned_) PetscFunctionReturn(0);
    const PetscInt s = s_index();
    // s = s(t) at the end of the step (statics: at the load time); the multiplier's force on s
    const double t = ctx.h > 0.0 ? ctx.t_end : ctx.t;
    const PetscInt lam = extra_offset();
    r.at(s) += ctx.x.at(lam);
    r.at(lam) += ctx.x.at(s) - (s0_ + travel(t));
    PetscFunctionReturn(0);
  }
  PetscErrorCode jacobian(const EvalContext& ctx, const MatSink& J) const override {
    PetscFunctionBeginUser;
    if (!owned_) PetscFunctionReturn(0);
    const PetscInt d[2] = {s_index(), extra_offset()};
    const double A[4] = {0.0, 1.0, 1.0, 0.0};
    (void)ctx;
    PetscCall(J.add(2, d, 2, d, A));
    PetscFunctionReturn(0);
  }

 private:
  double travel(double t) const {
    return by_distance_ ? distance_ * f_(t) : trapezoid_travel(t, speed_, start_, stop_, ramp_);
  }
  double speed_ = 0.0, start_, stop_, ramp_;
  bool by_distance_;
  double distance_ = 0.0;
  TimeFunction f_;
  std::string label_ = "slider_drive";
  double s0_ = 0.0;
  bool owned_ = false;
};

/// [[slider_drive]] force = F: a force along the track on the slider (see the file comment).
class SliderForce final : public Effect, public SlidingJointLink {
 public:
  SliderForce(const Model& m, const EffectParams& p)
      : SlidingJointLink(m, p, "slider_drive"),
        force_(p.number("force")),
        f_(p.string("tf_type", "").empty() ? TimeFunction{} : TimeFunction::from(p)) {
    for (const char* key : {"speed", "distance"})
      if (p.num.count(key)) throw ParamError(key, "give a `force`, or a travel (`speed` or `distance`), not both");
  }
  std::string type() const override { return "slider_drive"; }
  std::string label() const override { return label_; }
  bool time_dependent() const override { return true; }
  void distribute(const Model& m) override {
    label_ = link_label(m);
    owned_ = s_index() >= m.dof_map().owned_lo() && s_index() < m.dof_map().owned_hi();
  }
  void needed_dofs(const Model&, std::vector<PetscInt>& dofs) const override {
    if (owned_) dofs.push_back(s_index());
  }
  PetscErrorCode pattern(const Model&, const MatSink&) const override { return 0; }
  PetscErrorCode residual(const EvalContext& ctx, const LocalValues& r) const override {
    if (owned_) r.at(s_index()) -= force_ * f_(ctx.t);
    return 0;
  }
  PetscErrorCode jacobian(const EvalContext&, const MatSink&) const override { return 0; }

 private:
  double force_;
  TimeFunction f_;
  std::string label_ = "slider_drive";
  bool owned_ = false;
};

void register_slider_drive_effects(EffectRegistry& r) {
  using K = ParamSpec::Kind;
  EffectSpec s;
  s.type = "slider_drive";
  s.table = "slider_drive";
  s.meaning =
      "a driven slider, or a rope driven through a guide (a winch): its sliding coordinate follows a speed profile "
      "with start and stop ramps, or a distance times a time function; or a force along the track pushes it";
  s.role = EnergyRole::Driving;
  s.params = {
      optional_param({"beam", K::Beam, "", "the slider's beam (the slider of a [[sliding_joint]])", ""}),
      optional_param({"guide", K::Name, "",
                      "or: the [[guide]] whose rope it drives through, by its name (a winch: s, the rope's arc "
                      "length at the guide, growing pays rope out on the side of the rope's start)",
                      ""}),
      optional_param({"speed", K::Number, "m/s", "travel speed along the carrier (negative: toward its start)", ""}),
      optional_param({"distance", K::Number, "m",
                      "or: the travel along the carrier at f = 1 (negative: toward its start), s = s0 + distance "
                      "f(t)",
                      ""}),
      optional_param({"force", K::Number, "N",
                      "or: a force F f(t) along the track between slider and carrier, towards growing s (a "
                      "self-propelled trolley; at a guide, a drive wheel pulling the rope through): s is then free",
                      ""}),
      optional_param({"time_function", K::TimeFunction, "",
                      "with `distance`: f(t), starting at 0 (e.g. { type = \"smooth_ramp\", t0 = 0.5, t1 = 5.5 }); "
                      "with `force`: f(t) (default 1)",
                      ""}),
      {"start", K::Number, "s", "when the travel starts", "0.0", 0.0},
      {"stop", K::Number, "s", "when it has stopped (the ramp down ends here)", "inf"},
      {"ramp", K::Number, "s", "duration of the speed's rise and fall (0: a jump)", "0.0", 0.0},
  };
  r.add(s, [](const Model& m, const EffectParams& p) -> std::unique_ptr<Effect> {
    if (p.num.count("force")) return std::make_unique<SliderForce>(m, p);
    return std::make_unique<SliderDrive>(m, p);
  });
}

}  // namespace slidebeam::effects
