# The layers hold in the build: for each layer's CMake target, a header it may use compiles
# with that target's include roots and a header of a layer above it does not ("No such file").
# Run by CTest (layers_test) with each target's include directories, '|'-separated:
#   cmake -DCXX=c++ -DOUT=dir -DCORE=... -DWIRE=... -DCAMERA=... -DDAEMON=... -DCLIENT=...
#         -DCLI=... -P check_layers.cmake
cmake_minimum_required(VERSION 3.25)

file(MAKE_DIRECTORY ${OUT})

# probe(LAYER ROOTS HEADER EXPECT): EXPECT is "compiles" or "refused".
function(probe layer roots header expect)
  string(REPLACE "|" ";" dirs "${roots}")
  set(flags -std=c++20 -fsyntax-only)
  foreach(d IN LISTS dirs)
    if(d)
      list(APPEND flags -I${d})
    endif()
  endforeach()
  string(MAKE_C_IDENTIFIER "${layer}_${header}" name)
  set(source ${OUT}/${name}.cc)
  file(WRITE ${source} "#include \"${header}\"\n")
  execute_process(COMMAND ${CXX} ${flags} ${source} RESULT_VARIABLE rc ERROR_VARIABLE err
                  OUTPUT_QUIET)
  if(expect STREQUAL "compiles" AND NOT rc EQUAL 0)
    message(SEND_ERROR "${layer}: ${header} should compile:\n${err}")
  elseif(expect STREQUAL "refused")
    if(rc EQUAL 0)
      message(SEND_ERROR "${layer}: ${header} compiled, but it is above the layer")
    elseif(NOT err MATCHES "No such file")
      message(SEND_ERROR "${layer}: ${header} failed for another reason than its path:\n${err}")
    else()
      message(STATUS "${layer}: ${header} refused, as it should be")
    endif()
  endif()
endfunction()

probe(core "${CORE}" service/common/result.h compiles)
probe(core "${CORE}" service/pipeline/corner_pipeline.h compiles)
foreach(h idl/protocol/wire.h camera/frame_source.h service/server/service.h client/cli/args.h
          monocle/client.h)
  probe(core "${CORE}" ${h} refused)
endforeach()

probe(wire "${WIRE}" idl/protocol/wire.h compiles)
foreach(h camera/frame_source.h service/server/service.h client/cli/args.h monocle/client.h)
  probe(wire "${WIRE}" ${h} refused)
endforeach()

probe(camera "${CAMERA}" camera/recording_source.h compiles)
probe(camera "${CAMERA}" idl/protocol/cdr.h compiles)
foreach(h service/server/service.h client/cli/args.h monocle/client.h)
  probe(camera "${CAMERA}" ${h} refused)
endforeach()

probe(daemon "${DAEMON}" service/server/service_config.h compiles)
foreach(h client/cli/args.h monocle/client.h)
  probe(daemon "${DAEMON}" ${h} refused)
endforeach()

probe(client "${CLIENT}" monocle/client.h compiles)
foreach(h camera/frame_source.h service/server/service.h client/cli/args.h)
  probe(client "${CLIENT}" ${h} refused)
endforeach()

probe(cli "${CLI}" client/cli/args.h compiles)
probe(cli "${CLI}" monocle/client.h compiles)
probe(cli "${CLI}" camera/frame_source.h compiles)
probe(cli "${CLI}" service/server/service.h refused)
