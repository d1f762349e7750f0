// The server's messages as JSON for MCAP files (message encoding "json",
// schema encoding "jsonschema"), so Foxglove, the mcap CLI and other MCAP
// tools read a recording without a plugin. Field names follow the LCM types
// (lcmtypes/*.lcm). The numbers of the state streams (state, car state,
// contact) are written to a documented precision per field by default
// (positions to a millimetre, forces to a newton: the table in
// message_json.cpp and docs/logging.md, Size), or exactly (the shortest text
// that reads back as the same double), or to N significant digits. Commands
// and the applied-command log are always exact. Written by hand into one
// buffer: a recorder of 100 sessions at 2 kHz converts 200,000 messages a
// second.
#pragma once

#include <string>

#include <groundsim/applied_t.hpp>
#include <groundsim/car_state_t.hpp>
#include <groundsim/contact_state_t.hpp>
#include <groundsim/controls_t.hpp>
#include <groundsim/drive_t.hpp>
#include <groundsim/event_t.hpp>
#include <groundsim/state_t.hpp>

namespace groundsim::record {

// s as a JSON string, quotes included, appended to out: '"' and '\\'
// escaped, control characters as \u00XX, the rest as it is (UTF-8 passes).
void appendJsonString(std::string& out, const std::string& s);

// How the state streams' numbers are written. Simulated states carry noise
// in their low digits that no compressor removes (docs/logging.md, Size):
//   Fields: each quantity rounded to its own fixed decimals (the default);
//   Exact:  the shortest text that reads back as the same double;
//   Digits: N significant digits (1 to 16).
enum class Precision { Fields, Exact, Digits };
void setPrecision(Precision p, int digits = 17);
Precision precision();
// As the file's metadata says it: "fields-1" (the table's version), "exact",
// "digits-N". parsePrecision reads that back (and json_digits of files
// from before: "17" exact, else digits); false when it is neither.
std::string precisionName();
bool parsePrecision(const std::string& name, Precision* p, int* digits);
// The old switch: 17 is Exact, fewer Digits.
void setJsonDigits(int digits);
int jsonDigits();

std::string toJson(const groundsim::state_t& m);
std::string toJson(const groundsim::car_state_t& m);
std::string toJson(const groundsim::contact_state_t& m);
std::string toJson(const groundsim::event_t& m);
// A player's commands as the recorder heard them on the bus: never the
// token (a session's secret), plus the seq of the session's newest state
// when heard (a command applies from the step after it arrives).
std::string toJson(const groundsim::drive_t& m, long long after_seq);
std::string toJson(const groundsim::controls_t& m, long long after_seq);
// An entry of a session's applied-command log, always exact (whatever setJsonDigits said).
std::string toJson(const groundsim::applied_t& m);

// JSON Schemas (draft 2020-12) of the four, by schema name
// ("groundsim.state", "groundsim.car_state", "groundsim.contact_state",
// "groundsim.event").
const char* stateSchema();
const char* carStateSchema();
const char* contactStateSchema();
const char* eventSchema();
const char* driveSchema();
const char* controlsSchema();
const char* appliedSchema();

}  // namespace groundsim::record
