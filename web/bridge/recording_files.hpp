// The recordings folder's files (recordings.hpp): which names are served,
// and what a file holds: its sessions with their state counts and time
// spans, read from the file's statistics and chunk indexes.
#pragma once

#include <string>

#include "bridge/http_answer.hpp"

namespace groundsim::web {

// A plain .mcap file name of the folder: [A-Za-z0-9._-], not hidden, at most 200 characters.
bool plainRecordingName(const std::string& n);

// {name, bytes, complete, end, sessions:[{id, states, t0, t1}]} of the file
// at `path`. Throws what the MCAP reader throws.
std::string recordingJson(const std::string& name, const std::string& path);

// GET /recordings: the folder's first 200 recordings by name (one that
// cannot be read with its error), and whether there are more.
HttpAnswer recordingsListing(const std::string& dir);

}  // namespace groundsim::web
