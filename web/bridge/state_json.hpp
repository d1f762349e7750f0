// Wire messages of the server re-encoded as the JSON the page reads. Written
// by hand (snprintf into one buffer): a state of four cars is re-encoded in
// a few microseconds (bench/web), so the bridge adds nothing noticeable.
#pragma once

#include <string>

#include <groundsim/car_state_t.hpp>
#include <groundsim/contact_state_t.hpp>
#include <groundsim/event_t.hpp>
#include <groundsim/server_status_t.hpp>
#include <groundsim/state_t.hpp>

namespace groundsim::web {

// {"op":"state","session":..,"seq":..,"t":..,"status":..,"health":..,
//  "reason":..,"energy":..,"wall":..,"error_estimate" (the live error
//  estimate, -1 without a tolerance),"vehicles":[{"name","p","q"(w x y z),
//  "v","w","speed","spin","N","F","slip","contact"}]}
// wall: s on the bridge's steady clock when the state arrived, so the page
// measures the real-time factor even when its own thread is busy drawing.
std::string stateJson(const groundsim::state_t& s, double wall_s);
// {"op":"car","session","seq","t","cars":[{"vehicle","gear","rpm","power",
//  "yaw_rate","throttle","brake","steer","steer_angle","handbrake",
//  "gear_request","slip_ratio","slip_angle","travel"}]}
std::string carStateJson(const groundsim::car_state_t& s);
// {"op":"contact","session","seq","t","objects":[{"name","p" (shape centre),
//  "q" (w x y z),"v","w"}],"hits":[{"a","b","p","F" (on a),"impulse","peak",
//  "closing","depth","begin","hard"}]}: the objects with mass and the hits
// under way, with the seq of the state it goes with
std::string contactJson(const groundsim::contact_state_t& s);
// {"op":"event","session","severity","code","reason","t"}
std::string eventJson(const groundsim::event_t& e);
// A JSON string literal (quotes and escapes) for any bytes.
std::string quoted(const std::string& s);

}  // namespace groundsim::web
