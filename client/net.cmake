# `groundsim create|list|stop|reset|pause|resume|mode|step|watch|log|drive`:
# the LCM clients of groundsim-server. Included by client/CMakeLists.txt.
target_sources(groundsim PRIVATE
  ${CMAKE_CURRENT_LIST_DIR}/net_client.cpp
  ${CMAKE_CURRENT_LIST_DIR}/net_common.cpp
  ${CMAKE_CURRENT_LIST_DIR}/net_drive.cpp
  ${CMAKE_CURRENT_LIST_DIR}/net_log.cpp
  ${CMAKE_CURRENT_LIST_DIR}/net_session.cpp
  ${CMAKE_CURRENT_LIST_DIR}/net_terminal.cpp
  ${CMAKE_CURRENT_LIST_DIR}/net_tokens.cpp
  ${CMAKE_CURRENT_LIST_DIR}/net_watch.cpp
)
target_link_libraries(groundsim PRIVATE groundsim_lcm groundsim_scenario CLI11::CLI11 nlohmann_json::nlohmann_json)
