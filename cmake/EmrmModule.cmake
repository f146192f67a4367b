# emrm_add_module(NAME [USES module...] SOURCES file... [PUBLIC_LIBS lib...] [PRIVATE_LIBS lib...])
#
# Adds the library target emrm_NAME for the module whose headers are include/emrm/NAME and whose
# sources are listed. USES names the lower modules it may use; they must have been added before,
# which keeps the layers acyclic. The headers are not reached through include/ (which holds every
# module) but through a per-module folder in the build tree, ${PROJECT_BINARY_DIR}/layers/NAME,
# that holds only emrm/NAME (a link to include/emrm/NAME). A module's include path is thus its own
# folder plus those of the modules it uses (transitively, through PUBLIC linking): including a
# header of any other module fails to compile with "No such file or directory".
#
# Records, for the layering test and the umbrella target:
#   EMRM_MODULES             the modules in the order added (lowest first)
#   EMRM_MODULE_TARGETS      their targets
#   EMRM_MODULE_USES_<NAME>  the modules NAME names in USES
function(emrm_add_module name)
  cmake_parse_arguments(PARSE_ARGV 1 arg "" "" "USES;SOURCES;PUBLIC_LIBS;PRIVATE_LIBS")
  if(arg_UNPARSED_ARGUMENTS)
    message(FATAL_ERROR "emrm_add_module(${name}): unexpected arguments ${arg_UNPARSED_ARGUMENTS}")
  endif()
  set(target emrm_${name})
  foreach(used IN LISTS arg_USES)
    if(NOT TARGET emrm_${used})
      message(FATAL_ERROR "emrm_add_module(${name}): module '${used}' must be added before the modules that use it")
    endif()
  endforeach()

  set(layer_dir ${PROJECT_BINARY_DIR}/layers/${name})
  file(MAKE_DIRECTORY ${layer_dir}/emrm)
  if(NOT EXISTS ${layer_dir}/emrm/${name})
    file(CREATE_LINK ${PROJECT_SOURCE_DIR}/include/emrm/${name} ${layer_dir}/emrm/${name} SYMBOLIC)
  endif()

  add_library(${target} ${arg_SOURCES})
  add_library(emrm::${name} ALIAS ${target})
  set_target_properties(${target} PROPERTIES EXPORT_NAME ${name})  # installed as emrm::NAME
  target_include_directories(${target} PUBLIC
    $<BUILD_INTERFACE:${layer_dir}>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  list(TRANSFORM arg_USES PREPEND emrm_ OUTPUT_VARIABLE used_targets)
  target_link_libraries(${target}
    PUBLIC ${used_targets} ${arg_PUBLIC_LIBS}
    PRIVATE ${arg_PRIVATE_LIBS} $<BUILD_INTERFACE:emrm_warnings>)
  target_compile_features(${target} PUBLIC cxx_std_20)

  set(EMRM_MODULES ${EMRM_MODULES} ${name} PARENT_SCOPE)
  set(EMRM_MODULE_TARGETS ${EMRM_MODULE_TARGETS} ${target} PARENT_SCOPE)
  set(EMRM_MODULE_USES_${name} ${arg_USES} PARENT_SCOPE)
endfunction()
