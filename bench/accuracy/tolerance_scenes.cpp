#include "tolerance_scenes.hpp"

namespace groundsim::bench {

const std::vector<ToleranceScene>& toleranceScenes() {
  static const std::vector<ToleranceScene> scenes = {
      {"exp_plain", "plain.json", {}},
      {"exp_downhill", "downhill.json", {}},
      {"exp_uphill", "uphill.json", {}},
      {"exp_cosine", "cosine.json", {"duration=8"}},
      {"sedan_launch_brake", "sedan.json", {"duration=10"}},
      {"sedan_slalom", "sedan_slalom.json", {"duration=8"}},
      {"sedan_skidpad", "sedan_skidpad.json", {"duration=8"}},
      {"sedan_stick_slip", "sedan_stick_slip.json", {"duration=8"}},
      {"sedan_wet", "sedan_wet.json", {"duration=8"}},
      {"crash", "contact/crash.json", {}},
      {"lone_wheel_kerb", "accuracy/lone_wheel.json", {}},
      {"deformable_tyres", "accuracy/deformable_tyres.json", {}},
      {"sedan_hills_heightfield", "sedan_hills.json", {"duration=10"}},
      {"expression_ground", "expression.json", {}},
      {"eight_cars", "accuracy/eight_cars.json", {}},
      // four of the sedan's run for 20 s: what happens after a short pilot
      // (a spin on the wet road after 5 s) is the pilot's to see
      {"slalom_long", "sedan_slalom.json", {"duration=20"}},
      {"skidpad_long", "sedan_skidpad.json", {"duration=20"}},
      {"stick_slip_long", "sedan_stick_slip.json", {"duration=20"}},
      {"wet_long", "sedan_wet.json", {"duration=20"}},
      // issue 40's unseen scene: the sedan launched over a washboard,
      // corrugations 2 cm high every 0.8 m (its tyres shaken near wheel hop)
      {"sedan_washboard", "sedan.json",
       {"duration=6", R"J(ground={"type": "expression", "expression": "z - 0.02*cos(7.853981634*x)", "gradient_bound": 1.02})J"}},
  };
  return scenes;
}

scenario::Scenario loadToleranceScene(const std::string& configs, const ToleranceScene& sc) {
  const std::string path = configs + "/" + sc.config;
  nlohmann::json doc = scenario::loadScenarioDocument(path);
  for (const std::string& o : sc.overrides) scenario::applyOverride(doc, o);
  doc.erase("accuracy");
  return scenario::parseScenario(std::move(doc),
                                 scenario::FileAccess::local(path.substr(0, path.find_last_of('/'))));
}

}  // namespace groundsim::bench
