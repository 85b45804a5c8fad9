# statepack_add_archive: build a statepack archive as part of a CMake build.
#
#   statepack_add_archive(<target>
#     OUTPUT <archive.spk>            # where the archive goes (relative: to the current binary dir)
#     INPUTS <states.json>...         # notation files (relative: to the current source dir)
#     [SHADER_DIRS <dir>...]          # -s: shader and #include search directories
#     [RENDER_STATE_DIRS <dir>...]    # -r: notation search directories
#     [DEFINES NAME=VALUE...]         # -D: macros for every shader
#     [CONTENT_VERSION <n>]           # -v: user content version in the header
#     [VULKAN_VERSION 1.0|1.1|1.2|1.3]
#     [OPENGL]                        # also the OpenGL backend (--opengl) beside Vulkan
#     [PACKAGER <path or target>]     # default: the statepack target of this build, else the installed
#                                     # statepack::statepack (find_package), else `statepack` on PATH
#     [VERIFY]                        # also run `statepack verify` on the local Vulkan device
#     [CACHE_DIR <dir> | NO_CACHE]    # compile cache (--cache-dir); default: statepack-cache in the top
#                                     # binary dir, shared by every archive of the build
#     [REMOTE_CACHE <servers>]        # --remote-cache behind it (docs/cli.md "Teams and CI"); default:
#                                     # the cache variable STATEPACK_REMOTE_CACHE, else the environment's
#     [ARGS <extra packager args>...])
#
# Relative INPUTS are looked up in the current source dir, then in each RENDER_STATE_DIRS entry; one
# found nowhere (and not a GENERATED source) is an error at configure time. docs/cmake.md has a
# complete example and every keyword.
# The archive is a build product of <target> (built by `all`). The packager writes a depfile listing
# every JSON and shader file it read, so the archive is repacked exactly when one of them changes.
# The archive's path is stored in the target property STATEPACK_ARCHIVE. With VERIFY, every object of
# the archive is also created on the build machine's Vulkan device with the validation layer on (when
# installed), and the build fails on any error or validation message; a stamp file beside the archive
# records a passed verification, so it runs again only when the archive changes. A second target,
# <target>_watch (not built by `all`), runs the same pack with --watch: it repacks whenever an input
# changes, until Ctrl-C (docs/cli.md, "Development loop"); it does not verify.
set(STATEPACK_REMOTE_CACHE "" CACHE STRING
    "Compile cache servers behind every statepack_add_archive's local cache (ccache's remote_storage syntax)")

function(statepack_add_archive target)
  cmake_parse_arguments(PARSE_ARGV 1 ARG "VERIFY;OPENGL;NO_CACHE" "OUTPUT;CONTENT_VERSION;VULKAN_VERSION;PACKAGER;CACHE_DIR;REMOTE_CACHE"
                        "INPUTS;SHADER_DIRS;RENDER_STATE_DIRS;DEFINES;ARGS")
  # An unknown keyword first: it is usually a misspelt OUTPUT or INPUTS, which would otherwise be reported
  # as missing.
  if(ARG_UNPARSED_ARGUMENTS)
    message(FATAL_ERROR "statepack_add_archive(${target}): unknown arguments ${ARG_UNPARSED_ARGUMENTS} "
                        "(keywords: OUTPUT INPUTS SHADER_DIRS RENDER_STATE_DIRS DEFINES CONTENT_VERSION "
                        "VULKAN_VERSION OPENGL PACKAGER VERIFY CACHE_DIR NO_CACHE REMOTE_CACHE ARGS)")
  endif()
  if(NOT ARG_OUTPUT OR NOT ARG_INPUTS)
    message(FATAL_ERROR "statepack_add_archive(${target}): OUTPUT and INPUTS are required")
  endif()
  cmake_path(ABSOLUTE_PATH ARG_OUTPUT BASE_DIRECTORY "${CMAKE_CURRENT_BINARY_DIR}" NORMALIZE OUTPUT_VARIABLE output)

  if(ARG_PACKAGER)
    set(packager "${ARG_PACKAGER}")
  elseif(TARGET statepack)
    set(packager statepack)
  elseif(TARGET statepack::statepack)  # imported by find_package(statepack): the installed packager
    set(packager statepack::statepack)
  else()
    find_program(STATEPACK_EXECUTABLE statepack REQUIRED)
    set(packager "${STATEPACK_EXECUTABLE}")
  endif()
  if(TARGET ${packager})
    set(packager_command "$<TARGET_FILE:${packager}>")
    set(packager_dependency ${packager})
  else()
    set(packager_command "${packager}")
    set(packager_dependency "${packager}")
  endif()

  set(args pack -o "${output}" --vulkan --depfile "${output}.d")
  set(inputs "")
  # Each input is found now, as the packager will find it (the current source dir, then each
  # RENDER_STATE_DIRS entry, as Diligent's -r), so that a wrong path is this function's error at
  # configure time rather than the generator's "no rule to make target" at build time.
  foreach(input IN LISTS ARG_INPUTS)
    set(candidates "")
    foreach(base IN ITEMS "${CMAKE_CURRENT_SOURCE_DIR}" ${ARG_RENDER_STATE_DIRS})
      cmake_path(ABSOLUTE_PATH base BASE_DIRECTORY "${CMAKE_CURRENT_SOURCE_DIR}" NORMALIZE)
      cmake_path(ABSOLUTE_PATH input BASE_DIRECTORY "${base}" NORMALIZE OUTPUT_VARIABLE candidate)
      list(APPEND candidates "${candidate}")
    endforeach()
    set(found "")
    foreach(candidate IN LISTS candidates)
      get_source_file_property(generated "${candidate}" GENERATED)
      if(EXISTS "${candidate}" OR generated)
        set(found "${candidate}")
        break()
      endif()
    endforeach()
    if(NOT found)
      list(JOIN candidates ", " looked)
      message(FATAL_ERROR "statepack_add_archive(${target}): INPUTS file '${input}' not found (looked for ${looked})")
    endif()
    list(APPEND args -i "${found}")
    list(APPEND inputs "${found}")
  endforeach()
  foreach(dir IN LISTS ARG_SHADER_DIRS)
    cmake_path(ABSOLUTE_PATH dir BASE_DIRECTORY "${CMAKE_CURRENT_SOURCE_DIR}" NORMALIZE)
    list(APPEND args -s "${dir}")
  endforeach()
  foreach(dir IN LISTS ARG_RENDER_STATE_DIRS)
    cmake_path(ABSOLUTE_PATH dir BASE_DIRECTORY "${CMAKE_CURRENT_SOURCE_DIR}" NORMALIZE)
    list(APPEND args -r "${dir}")
  endforeach()
  foreach(define IN LISTS ARG_DEFINES)
    list(APPEND args -D "${define}")
  endforeach()
  if(DEFINED ARG_CONTENT_VERSION)
    list(APPEND args -v "${ARG_CONTENT_VERSION}")
  endif()
  if(ARG_VULKAN_VERSION)
    list(APPEND args --vulkan_version "${ARG_VULKAN_VERSION}")
  endif()
  if(ARG_OPENGL)
    list(APPEND args --opengl)
  endif()
  # Unchanged shaders are not compiled again when one changes (the archive is the same bytes either way).
  if(ARG_NO_CACHE AND ARG_CACHE_DIR)
    message(FATAL_ERROR "statepack_add_archive(${target}): CACHE_DIR and NO_CACHE exclude each other")
  elseif(NOT ARG_NO_CACHE)
    if(ARG_CACHE_DIR)
      cmake_path(ABSOLUTE_PATH ARG_CACHE_DIR BASE_DIRECTORY "${CMAKE_CURRENT_BINARY_DIR}" NORMALIZE OUTPUT_VARIABLE cache_dir)
    else()
      set(cache_dir "${CMAKE_BINARY_DIR}/statepack-cache")
    endif()
    list(APPEND args --cache-dir "${cache_dir}")
    # A team's servers behind it: the keyword, else the cache variable (-DSTATEPACK_REMOTE_CACHE=...), else
    # $STATEPACK_REMOTE_CACHE as the build runs (read by statepack itself).
    if(DEFINED ARG_REMOTE_CACHE)
      list(APPEND args --remote-cache "${ARG_REMOTE_CACHE}")
    elseif(STATEPACK_REMOTE_CACHE)
      list(APPEND args --remote-cache "${STATEPACK_REMOTE_CACHE}")
    endif()
  elseif(DEFINED ARG_REMOTE_CACHE)
    message(FATAL_ERROR "statepack_add_archive(${target}): REMOTE_CACHE sits behind the local cache; drop NO_CACHE")
  else()
    list(APPEND args --remote-cache=)  # no server either, whatever $STATEPACK_REMOTE_CACHE says
  endif()
  list(APPEND args ${ARG_ARGS})

  # Ninja creates an output's directory itself; Make and the Visual Studio generators do not.
  cmake_path(GET output PARENT_PATH output_dir)
  add_custom_command(
    OUTPUT "${output}"
    COMMAND ${CMAKE_COMMAND} -E make_directory "${output_dir}"
    COMMAND ${packager_command} ${args}
    DEPENDS ${inputs} ${packager_dependency}
    DEPFILE "${output}.d"
    WORKING_DIRECTORY "${CMAKE_CURRENT_SOURCE_DIR}"
    COMMENT "statepack: packing ${output}"
    VERBATIM)
  set(products "${output}")
  if(ARG_VERIFY)
    add_custom_command(
      OUTPUT "${output}.verified"
      COMMAND ${packager_command} verify "${output}"
      COMMAND ${CMAKE_COMMAND} -E touch "${output}.verified"
      DEPENDS "${output}" ${packager_dependency}
      COMMENT "statepack: verifying ${output} on the local Vulkan device"
      VERBATIM)
    list(APPEND products "${output}.verified")
  endif()
  add_custom_target(${target} ALL DEPENDS ${products})
  set_target_properties(${target} PROPERTIES STATEPACK_ARCHIVE "${output}")

  # <target>_watch (not built by `all`): the same pack command line with --watch, in the terminal. It
  # packs, then repacks the archive (and its depfile) whenever a file the pack read changes, until Ctrl-C.
  add_custom_target(${target}_watch
    COMMAND ${CMAKE_COMMAND} -E make_directory "${output_dir}"
    COMMAND ${packager_command} ${args} --watch
    WORKING_DIRECTORY "${CMAKE_CURRENT_SOURCE_DIR}"
    COMMENT "statepack: watching the inputs of ${output} (Ctrl-C to stop)"
    USES_TERMINAL
    VERBATIM)
  if(TARGET ${packager})
    get_target_property(packager_imported ${packager} IMPORTED)
    if(NOT packager_imported)
      add_dependencies(${target}_watch ${packager})  # a packager of this build is built first
    endif()
  endif()
endfunction()
