# `groundsim create|list|stop|reset|pause|resume|mode|step|watch|log|drive`:
# the LCM clients of groundsim-server (client/net/). They share the protocol
# library with the server and do not link the session layer. Included by
# client/CMakeLists.txt.
target_sources(groundsim PRIVATE
  ${CMAKE_CURRENT_LIST_DIR}/net/car_drive.cpp
  ${CMAKE_CURRENT_LIST_DIR}/net/client.cpp
  ${CMAKE_CURRENT_LIST_DIR}/net/common.cpp
  ${CMAKE_CURRENT_LIST_DIR}/net/create.cpp
  ${CMAKE_CURRENT_LIST_DIR}/net/drive.cpp
  ${CMAKE_CURRENT_LIST_DIR}/net/log.cpp
  ${CMAKE_CURRENT_LIST_DIR}/net/record.cpp
  ${CMAKE_CURRENT_LIST_DIR}/record/file_commands.cpp
  ${CMAKE_CURRENT_LIST_DIR}/record/ledger.cpp
  ${CMAKE_CURRENT_LIST_DIR}/record/recorder.cpp
  ${CMAKE_CURRENT_LIST_DIR}/record/replay.cpp
  ${CMAKE_CURRENT_LIST_DIR}/net/session_commands.cpp
  ${CMAKE_CURRENT_LIST_DIR}/net/terminal.cpp
  ${CMAKE_CURRENT_LIST_DIR}/net/tokens.cpp
  ${CMAKE_CURRENT_LIST_DIR}/net/watch.cpp
)
# commands.hpp and the CSV writer shared with `run` (run/telemetry_csv.hpp) are in client/
target_include_directories(groundsim PRIVATE ${CMAKE_CURRENT_LIST_DIR})
target_link_libraries(groundsim PRIVATE groundsim_protocol groundsim_scenario groundsim_recording CLI11::CLI11 nlohmann_json::nlohmann_json)
# `replay --resimulate` re-simulates a recording as the server ran it: the
# stepping layer's Resimulator (the code a session steps with, below the
# session layer) and the adapter's frame conversion (server/lcm/convert.cpp),
# so that its states are the server's to the bit. No hosting code is linked:
# tests/layers checks that no groundsim::session symbol reaches the CLI.
target_link_libraries(groundsim PRIVATE groundsim_stepping groundsim_lcm)
