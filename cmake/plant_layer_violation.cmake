# The layering test's power (CTest "layering_planted"): copies of src/ and app/ with one planted
# violation each -- an include that points up (scene -> frame), one algorithm including another
# (restir_gi -> restir_di), Embree outside src/backends -- must each fail check_layers.cmake,
# naming the planted file.
#   cmake -DROOT=<checkout> -DOUT=<scratch folder> -P cmake/plant_layer_violation.cmake
cmake_minimum_required(VERSION 3.22)
set(plants "src/scene/scene.h|#include \"frame/gbuffer.h\""
           "src/integrators/restir_gi/restir_gi_frame.h|#include \"integrators/restir_di/light_tiles.h\""
           "src/frame/render.cpp|#include <embree3/rtcore.h>")
foreach(plant ${plants})
  string(REPLACE "|" ";" parts "${plant}")
  list(GET parts 0 file)
  list(GET parts 1 line)
  file(REMOVE_RECURSE ${OUT})
  file(COPY ${ROOT}/src ${ROOT}/app DESTINATION ${OUT})
  file(APPEND ${OUT}/${file} "\n${line}\n")
  execute_process(COMMAND ${CMAKE_COMMAND} -DROOT=${OUT} -P ${ROOT}/cmake/check_layers.cmake RESULT_VARIABLE rc OUTPUT_VARIABLE out
                  ERROR_VARIABLE err)
  if(rc EQUAL 0 OR NOT "${out}${err}" MATCHES "${file}")
    message(FATAL_ERROR "the layering check missed a planted violation: ${file}: ${line}\n${out}${err}")
  endif()
  message("planted ${file}: ${line} -- caught")
endforeach()
file(REMOVE_RECURSE ${OUT})
