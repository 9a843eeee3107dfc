# omnidso_add_library(NAME DEPS...): a library from NAME/src/*.cc with public headers in
# NAME/include, exported as omnidso::NAME. Header-only until it has sources.
function(omnidso_warnings target scope)
  target_compile_options(${target} ${scope} -Wall -Wextra)
  if(OMNIDSO_WERROR)
    target_compile_options(${target} ${scope} -Werror)
  endif()
endfunction()

function(omnidso_add_library name)
  file(GLOB_RECURSE sources CONFIGURE_DEPENDS "${CMAKE_CURRENT_SOURCE_DIR}/src/*.cc")
  if(sources)
    add_library(omnidso_${name} ${sources})
    set(scope PUBLIC)
    omnidso_warnings(omnidso_${name} PRIVATE)
  else()
    add_library(omnidso_${name} INTERFACE)
    set(scope INTERFACE)
  endif()
  add_library(omnidso::${name} ALIAS omnidso_${name})
  set_target_properties(omnidso_${name} PROPERTIES EXPORT_NAME ${name})
  if(sources)
    set_target_properties(omnidso_${name} PROPERTIES OUTPUT_NAME omnidso_${name})
  endif()
  target_include_directories(omnidso_${name} ${scope}
    $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
    $<INSTALL_INTERFACE:include>)
  target_link_libraries(omnidso_${name} ${scope} ${ARGN})
  install(TARGETS omnidso_${name} EXPORT omnidsoTargets
          ARCHIVE DESTINATION lib LIBRARY DESTINATION lib RUNTIME DESTINATION bin)
  install(DIRECTORY include/ DESTINATION include)
endfunction()

# omnidso_add_test_suite(NAME DIR DEPS... [LABELS label...]): one gtest executable from
# tests/DIR/*_test.cc; LABELS go to every test (`slow` keeps them out of `make test`).
# Tests read real data from OMNIDSO_DATA_DIR (environment) and skip when it is absent.
function(omnidso_add_test_suite name dir)
  cmake_parse_arguments(ARG "" "" "LABELS" ${ARGN})
  file(GLOB sources CONFIGURE_DEPENDS "${CMAKE_CURRENT_SOURCE_DIR}/${dir}/*.cc")
  if(NOT sources)
    return()
  endif()
  add_executable(${name} ${sources})
  target_link_libraries(${name} PRIVATE ${ARG_UNPARSED_ARGUMENTS} GTest::gtest GTest::gtest_main)
  target_include_directories(${name} PRIVATE "${CMAKE_CURRENT_SOURCE_DIR}")
  omnidso_warnings(${name} PRIVATE)
  set(labels ${ARG_LABELS})
  if(NOT labels)
    set(labels fast)
  endif()
  gtest_discover_tests(${name}
    PROPERTIES ENVIRONMENT "OMNIDSO_DATA_DIR=${OMNIDSO_DATA_DIR}" LABELS "${labels}"
    DISCOVERY_TIMEOUT 60)
endfunction()
