# `groundsim run`: the embedded runner (no network), and the CSV writer the
# network logger shares. Included by client/CMakeLists.txt.
target_sources(groundsim PRIVATE
  ${CMAKE_CURRENT_LIST_DIR}/run_command.cpp
  ${CMAKE_CURRENT_LIST_DIR}/speed_plot.cpp
  ${CMAKE_CURRENT_LIST_DIR}/telemetry_csv.cpp
)
# "telemetry_csv.hpp" for the network logger too
target_include_directories(groundsim PRIVATE ${CMAKE_CURRENT_LIST_DIR})
target_link_libraries(groundsim PRIVATE groundsim_scenario groundsim_accuracy CLI11::CLI11)
