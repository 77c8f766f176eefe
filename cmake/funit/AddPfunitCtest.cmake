# Fallback for pFUnit's add_pfunit_ctest() where pFUnit is not installed (docs/testing.md).
#
# Including this file defines
#   - the library target `funit` (cmake/funit/funit.f90, the runtime the translated tests call);
#   - funit_add_executable(<name> TEST_SOURCES <file.pf>... [OTHER_SOURCES ...] [LINK_LIBRARIES ...]
#     [TRANSLATOR_OPTIONS ...]) which translates each .pf file with pf2f90.py and builds one test
#     executable;
#   - add_pfunit_ctest(<name> TEST_SOURCES ... [OTHER_SOURCES ...] [LINK_LIBRARIES ...] [LABELS ...]
#     [MAX_PES n] [WORKING_DIRECTORY dir] [REGISTRY ...] [EXTRA_USE ...] [EXTRA_INITIALIZE ...]
#     [EXTRA_FINALIZE ...]) with the signature of pFUnit's, unless real pFUnit already defined it.
# MAX_PES, REGISTRY and the EXTRA_* hooks are accepted for compatibility and have no effect: the
# fallback runs serially and finds the tests itself.
include_guard(GLOBAL)

find_package(Python3 REQUIRED COMPONENTS Interpreter)
# Kept in the cache: the guard above means this file runs once, but its functions are called from
# other directories, where the imported target Python3::Interpreter is not visible.
set(FUNIT_PYTHON ${Python3_EXECUTABLE} CACHE INTERNAL "python3 that runs pf2f90.py")
set(FUNIT_TRANSLATOR ${CMAKE_CURRENT_LIST_DIR}/pf2f90.py CACHE INTERNAL "pFUnit .pf translator")

add_library(funit STATIC ${CMAKE_CURRENT_LIST_DIR}/funit.f90)
set_target_properties(funit PROPERTIES Fortran_MODULE_DIRECTORY ${PROJECT_BINARY_DIR}/funit_modules)
target_include_directories(funit PUBLIC $<BUILD_INTERFACE:${PROJECT_BINARY_DIR}/funit_modules>)
target_compile_options(funit PRIVATE ${UNIARC_COMMON_FLAGS})

function(funit_add_executable name)
  cmake_parse_arguments(PARSE_ARGV 1 FUNIT "" "" "TEST_SOURCES;OTHER_SOURCES;LINK_LIBRARIES;TRANSLATOR_OPTIONS")
  if(NOT FUNIT_TEST_SOURCES)
    message(FATAL_ERROR "funit_add_executable(${name}): no TEST_SOURCES")
  endif()
  set(generated)
  set(modules)
  foreach(pf_file IN LISTS FUNIT_TEST_SOURCES)
    # Relative paths are in the source directory, as with pFUnit.
    get_filename_component(pf_path ${pf_file} ABSOLUTE BASE_DIR ${CMAKE_CURRENT_SOURCE_DIR})
    get_filename_component(module ${pf_file} NAME_WE)
    set(f90_file ${CMAKE_CURRENT_BINARY_DIR}/${name}_sources/${module}.f90)
    add_custom_command(
      OUTPUT ${f90_file}
      COMMAND ${CMAKE_COMMAND} -E make_directory ${CMAKE_CURRENT_BINARY_DIR}/${name}_sources
      COMMAND ${FUNIT_PYTHON} ${FUNIT_TRANSLATOR} ${FUNIT_TRANSLATOR_OPTIONS} ${pf_path} -o ${f90_file}
      DEPENDS ${pf_path} ${FUNIT_TRANSLATOR}
      COMMENT "Translating ${pf_file} (pFUnit fallback)"
      VERBATIM)
    list(APPEND generated ${f90_file})
    list(APPEND modules ${module})
  endforeach()
  set(driver ${CMAKE_CURRENT_BINARY_DIR}/${name}_sources/${name}_driver.f90)
  add_custom_command(
    OUTPUT ${driver}
    COMMAND ${CMAKE_COMMAND} -E make_directory ${CMAKE_CURRENT_BINARY_DIR}/${name}_sources
    COMMAND ${FUNIT_PYTHON} ${FUNIT_TRANSLATOR} --driver ${driver} ${modules}
    DEPENDS ${FUNIT_TRANSLATOR}
    COMMENT "Writing the driver of ${name} (pFUnit fallback)"
    VERBATIM)

  add_executable(${name} ${generated} ${driver} ${FUNIT_OTHER_SOURCES})
  # Each test executable has its own module directory: test modules of different executables may
  # share names (the generated *_suite modules certainly would if a .pf file were used twice).
  set_target_properties(${name} PROPERTIES
    Fortran_MODULE_DIRECTORY ${CMAKE_CURRENT_BINARY_DIR}/${name}_modules)
  target_compile_options(${name} PRIVATE ${UNIARC_COMMON_FLAGS})
  target_link_libraries(${name} PRIVATE funit ${FUNIT_LINK_LIBRARIES})
endfunction()

if(NOT COMMAND add_pfunit_ctest)
  function(add_pfunit_ctest name)
    cmake_parse_arguments(PARSE_ARGV 1 PF_TEST ""
      "REGISTRY;MAX_PES;EXTRA_USE;EXTRA_INITIALIZE;EXTRA_FINALIZE;WORKING_DIRECTORY"
      "TEST_SOURCES;OTHER_SOURCES;LINK_LIBRARIES;LABELS")
    funit_add_executable(${name}
      TEST_SOURCES ${PF_TEST_TEST_SOURCES}
      OTHER_SOURCES ${PF_TEST_OTHER_SOURCES}
      LINK_LIBRARIES ${PF_TEST_LINK_LIBRARIES})
    if(PF_TEST_WORKING_DIRECTORY)
      set(workdir ${PF_TEST_WORKING_DIRECTORY})
    else()
      set(workdir ${CMAKE_CURRENT_BINARY_DIR})
    endif()
    add_test(NAME ${name} COMMAND ${name} WORKING_DIRECTORY ${workdir})
    if(PF_TEST_LABELS)
      set_tests_properties(${name} PROPERTIES LABELS "${PF_TEST_LABELS}")
    endif()
  endfunction()
endif()
