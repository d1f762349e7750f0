// The concrete integrators (one file each); see integrator.hpp.
#pragma once

#include "integrator.hpp"

namespace groundsim {

class SemiImplicitEuler final : public Integrator {
 public:
  void advance(const Model& m, State& s, Workspace& ws, double h) override;
  const char* name() const override { return "semi_implicit_euler"; }
};

}  // namespace groundsim
