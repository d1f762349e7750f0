// Validators of the scenario's sections, one file each: each reads its
// object through an ObjectReader (recording issues, filling defaults) and
// returns the typed settings.
#pragma once

#include "physics/core/model.hpp"
#include "scenario/accuracy_spec.hpp"
#include "scenario/file_access.hpp"
#include "scenario/ground_spec.hpp"
#include "scenario/object_reader.hpp"
#include "scenario/object_spec.hpp"
#include "scenario/race_spec.hpp"
#include "scenario/task_spec.hpp"
#include "scenario/vehicle_spec.hpp"

namespace groundsim::scenario {

// physics_section.cpp: `physics` (integrator, step, gravity, limits) and
// `contact` (ground stiffness, damping, friction).
void readPhysics(ObjectReader physics, Options& opt);
void readContact(ObjectReader contact, ContactParams& c);
// ground_section.cpp: the budget bounds the expression's length (checked
// before muParser sees it) and a heightfield's samples; files: where a
// heightfield's file may be read.
GroundSpec readGround(ObjectReader ground, const Budget& budget, const FileAccess& files);
// vehicle_section.cpp: one vehicle object.
VehicleSpec readVehicle(ObjectReader vehicle);
// road_car_section.cpp: the keys of a road car, and its `controls` table
// (gears: how many forward gears a "gear" entry may name).
void readRoadCar(ObjectReader& vehicle, RoadCarParams& p);
std::vector<TimedControls> readControlTable(ObjectReader& vehicle, int gears);
// objects_section.cpp: `collisions` (contact between bodies) and `objects`,
// whose names must differ from each other and from the vehicles'.
void readCollisions(ObjectReader collisions, CollisionParams& c);
std::vector<ObjectEntry> readObjects(ObjectReader& top, const std::vector<VehicleSpec>& vehicles);
// task_section.cpp: the `task` section, checked against the vehicles read.
TaskSpec readTask(ObjectReader task, const std::vector<VehicleSpec>& vehicles);

// accuracy_section.cpp: `accuracy` (the error a user accepts).
AccuracySpec readAccuracy(ObjectReader accuracy);

// race_section.cpp: `race` (gates, laps, start grid, boundary) for a
// scenario of `vehicles` vehicles.
RaceSpec readRace(ObjectReader race, int vehicles);

}  // namespace groundsim::scenario
