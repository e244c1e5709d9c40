// SPDX-License-Identifier: MIT
/// @file Print the effect registry's specs as JSON: the build writes them to
/// python/slidebeam/effect_specs.json, the schema of the scene's effect tables.

#include "model/effect.hpp"

#include <iostream>

int main() {
  std::cout << slidebeam::EffectRegistry::instance().specs_json();
  return 0;
}
