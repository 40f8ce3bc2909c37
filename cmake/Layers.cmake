# The layers of rockdem, bottom up, and the rule that holds them together: a file may include
# files of its own layer and of the layers its layer uses (directly or through them), nothing
# else. docs/architecture.md explains the layers; this list is the one place that defines them.
# The rule is checked at configure time (a violation stops the build) and by the test
# `architecture.layers` (cmake -P cmake/check_layers.cmake).
#
# ROCKDEM_LAYER_<name>_DIR   folder of the layer (all sources below it belong to it)
# ROCKDEM_LAYER_<name>_USES  the layers right below it that it builds on
set(ROCKDEM_LAYERS core plugin_api geometry seismic model contact boundary mechanics parallel io
    lab simulation analysis app models)

set(ROCKDEM_LAYER_core_DIR framework/core)              # ids, units, typed parameters, errors, registry
set(ROCKDEM_LAYER_core_USES "")
set(ROCKDEM_LAYER_plugin_api_DIR framework/plugin_api)  # contracts that models/ implements
set(ROCKDEM_LAYER_plugin_api_USES core)
set(ROCKDEM_LAYER_geometry_DIR framework/geometry)      # polygons, meshing
set(ROCKDEM_LAYER_geometry_USES core)
set(ROCKDEM_LAYER_seismic_DIR framework/seismic)        # accelerograms, filtering, SDOF
set(ROCKDEM_LAYER_seismic_USES core)
set(ROCKDEM_LAYER_model_DIR framework/model)            # the model's data: blocks, gridpoints, zones, contacts
set(ROCKDEM_LAYER_model_USES plugin_api geometry)
set(ROCKDEM_LAYER_contact_DIR framework/contact)        # contact detection
set(ROCKDEM_LAYER_contact_USES model)
set(ROCKDEM_LAYER_boundary_DIR framework/boundary)      # boundary conditions, time functions
set(ROCKDEM_LAYER_boundary_USES model seismic)  # seismic: boundaries that apply ground motions
set(ROCKDEM_LAYER_mechanics_DIR framework/mechanics)    # time stepping, zones, damping
set(ROCKDEM_LAYER_mechanics_USES contact boundary)
set(ROCKDEM_LAYER_parallel_DIR framework/parallel)      # MPI: the only layer that sees a communicator
set(ROCKDEM_LAYER_parallel_USES mechanics)
set(ROCKDEM_LAYER_io_DIR framework/io)                  # case files, HDF5, VTK, CSV, checkpoints
set(ROCKDEM_LAYER_io_USES mechanics)
set(ROCKDEM_LAYER_lab_DIR framework/lab)                # element driver, lab cases, specimen, virtual lab
set(ROCKDEM_LAYER_lab_USES io)
set(ROCKDEM_LAYER_simulation_DIR framework/simulation)  # running a case: stages, recorders, progress
set(ROCKDEM_LAYER_simulation_USES lab parallel)
set(ROCKDEM_LAYER_analysis_DIR framework/analysis)      # segmentation, compare, calibrate, diagnose
set(ROCKDEM_LAYER_analysis_USES lab)
set(ROCKDEM_LAYER_app_DIR framework/app)                # the rockdem subcommands
set(ROCKDEM_LAYER_app_USES simulation analysis seismic)
set(ROCKDEM_LAYER_models_DIR models)                    # plug-ins: joint laws, effects, rock materials
set(ROCKDEM_LAYER_models_USES plugin_api)

# ROCKDEM_LAYER_<name>_BELOW: every layer <name> may include, itself excluded: the layers it
# uses, the layers those use, and so on (a breadth-first walk over USES).
foreach(layer IN LISTS ROCKDEM_LAYERS)
  set(queue ${ROCKDEM_LAYER_${layer}_USES})
  set(below "")
  while(queue)
    list(POP_FRONT queue used)
    if(NOT used IN_LIST ROCKDEM_LAYERS)
      message(FATAL_ERROR "cmake/Layers.cmake: layer '${layer}' uses '${used}', which is not a layer")
    endif()
    if(NOT used IN_LIST below)
      list(APPEND below ${used})
      list(APPEND queue ${ROCKDEM_LAYER_${used}_USES})
    endif()
  endwhile()
  set(ROCKDEM_LAYER_${layer}_BELOW ${below})
endforeach()

# The layer a repository path (framework/<x>/... or models/...) belongs to; "" if none.
function(rockdem_layer_of path out)
  set(found "")
  foreach(layer IN LISTS ROCKDEM_LAYERS)
    string(LENGTH "${ROCKDEM_LAYER_${layer}_DIR}/" n)
    string(SUBSTRING "${path}" 0 ${n} head)
    if(head STREQUAL "${ROCKDEM_LAYER_${layer}_DIR}/")
      set(found ${layer})
    endif()
  endforeach()
  set(${out} "${found}" PARENT_SCOPE)
endfunction()

# Check every source of every layer; sets <out> to the list of violations (empty when clean),
# each "file:line includes <path>: layer a may not include layer b (a may include: ...)".
function(rockdem_check_layers root out)
  set(problems "")
  file(GLOB_RECURSE sources RELATIVE ${root} ${root}/framework/* ${root}/models/*)
  foreach(f IN LISTS sources)
    if(NOT f MATCHES "\\.(hpp|cpp|h|hpp\\.in)$")
      continue()
    endif()
    rockdem_layer_of(${f} layer)
    if(layer STREQUAL "")
      list(APPEND problems "${f}: in no layer; add its folder to cmake/Layers.cmake")
      continue()
    endif()
    file(STRINGS ${root}/${f} lines)
    set(lineno 0)
    foreach(line IN LISTS lines)
      math(EXPR lineno "${lineno} + 1")
      if(line MATCHES "^[ \t]*#[ \t]*include[ \t]*\"((framework|models)/[^\"]+)\"")
        set(target "${CMAKE_MATCH_1}")
        rockdem_layer_of(${target} to)
        if(to STREQUAL "")
          list(APPEND problems "${f}:${lineno} includes ${target}, which is in no layer")
        elseif(NOT to STREQUAL layer AND NOT to IN_LIST ROCKDEM_LAYER_${layer}_BELOW)
          string(REPLACE ";" ", " may "${ROCKDEM_LAYER_${layer}_BELOW}")
          list(APPEND problems "${f}:${lineno} includes ${target}: layer '${layer}' may not include layer '${to}' (it may include: ${may})")
        endif()
      endif()
    endforeach()
  endforeach()
  set(${out} "${problems}" PARENT_SCOPE)
endfunction()
