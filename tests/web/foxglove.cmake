# The bridge's Foxglove WebSocket endpoint (groundsim-web --foxglove-port).
# Included by tests/web/CMakeLists.txt.

# Its parts without sockets: subprotocols, client messages, channels, feed.
add_executable(web_foxglove_tests foxglove_test.cpp)
target_link_libraries(web_foxglove_tests PRIVATE groundsim_web GTest::gtest_main)
gtest_discover_tests(web_foxglove_tests TEST_PREFIX web. PROPERTIES LABELS web)

# Clients on the wire as Foxglove and Lichtblick are: npm's
# @foxglove/ws-protocol (foxglove.websocket.v1) and raw `ws` clients
# (foxglove.sdk.v1), against the real groundsim-server and groundsim-web in
# a network namespace of their own (netns_run.sh). No browser; node and the
# page's npm packages (web/package.json) only.
find_program(NODE_EXECUTABLE node)
function(groundsim_foxglove_test name script)
  if(NOT GROUNDSIM_WEB_PAGE)
    groundsim_skipped_test(web.${name} "no node/npm: the page's npm packages are not installed (scripts/setup-web.sh)" web)
    return()
  endif()
  add_test(NAME web.${name}
    COMMAND ${PROJECT_SOURCE_DIR}/tests/integration/netns_run.sh
            ${NODE_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/${script} ${ARGN})
  set_tests_properties(web.${name} PROPERTIES
    SKIP_RETURN_CODE 77 TIMEOUT 180 LABELS web
    ENVIRONMENT "GROUNDSIM_SERVER=$<TARGET_FILE:groundsim-server>;GROUNDSIM_WEB=$<TARGET_FILE:groundsim-web>;GROUNDSIM_CLI=$<TARGET_FILE:groundsim>;GROUNDSIM_CONFIG_DIR=${PROJECT_SOURCE_DIR}/configs;GROUNDSIM_WEB_NODE_MODULES=${GROUNDSIM_WEB_NODE_MODULES}")
endfunction()

# a created session's channels advertised and unadvertised with it; its
# states validate against the advertised schema, seq increasing with no gap;
# both subprotocols, others refused with 400
groundsim_foxglove_test(FoxgloveLiveSession foxglove_live.mjs)
# hostile messages answered with status errors naming the field, an
# oversized message closing its client alone, a stalled client's oldest
# messages dropped and counted, while a good client gets every state
groundsim_foxglove_test(FoxgloveHostileAndSlowClients foxglove_hostile.mjs)
