// SPDX-License-Identifier: MIT
#include "model/effect.hpp"

namespace slidebeam {
namespace effects {
void register_beam_effects(EffectRegistry& r);
void register_ancf_effects(EffectRegistry& r);
void register_load_effects(EffectRegistry& r);
void register_support_effects(EffectRegistry& r);
void register_joint_effects(EffectRegistry& r);
void register_sliding_effects(EffectRegistry& r);
void register_damping_effects(EffectRegistry& r);
void register_slider_drive_effects(EffectRegistry& r);
void register_drag_effects(EffectRegistry& r);
void register_added_mass_effects(EffectRegistry& r);
void register_friction_effects(EffectRegistry& r);
void register_contact_effects(EffectRegistry& r);
void register_contact_friction_effects(EffectRegistry& r);
void register_contact_damping_effects(EffectRegistry& r);
void register_buoyancy_effects(EffectRegistry& r);
void register_body_effects(EffectRegistry& r);
}  // namespace effects

void register_builtin_effects(EffectRegistry& registry) {
  effects::register_beam_effects(registry);
  effects::register_body_effects(registry);
  effects::register_ancf_effects(registry);
  effects::register_load_effects(registry);
  effects::register_support_effects(registry);
  effects::register_joint_effects(registry);
  effects::register_sliding_effects(registry);
  effects::register_damping_effects(registry);
  effects::register_slider_drive_effects(registry);
  effects::register_drag_effects(registry);
  effects::register_added_mass_effects(registry);
  effects::register_friction_effects(registry);
  effects::register_contact_effects(registry);
  effects::register_contact_friction_effects(registry);
  effects::register_contact_damping_effects(registry);
  effects::register_buoyancy_effects(registry);
}

}  // namespace slidebeam
