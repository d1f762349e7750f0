// The scenes of the sweep. Analytic ones compare with a closed form; the
// report's four experiments compare with a reference run of the same model
// (RK4 at a small step).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "cell.hpp"

namespace groundsim::accuracy {

struct Scene {
  std::string name;
  std::string answer;         // what the error is measured against (docs)
  bool uses_fidelity = true;  // a car scene: swept over the wheel models
  std::function<Result(const Setting&)> run;
};

// free_fall, spring_mass, drop_bounce, incline_30, plain_s1, parked_20, skid_stop
std::vector<Scene> analyticScenes();

// plain, downhill, uphill, cosine: final chassis position against `reference`
// (the same scene run at the reference setting).
std::vector<Scene> reportExperiments();
Result runExperiment(const std::string& name, const Setting& s);

}  // namespace groundsim::accuracy
