# Writes a header holding the text of every monocle_msgs .msg and .srv file as a C++ raw string,
# for the ros2msg schemas of recordings. Run at configure time by client/CMakeLists.txt.
function(monocle_embed_msgs dir out)
  file(GLOB files ${dir}/msg/*.msg ${dir}/srv/*.srv)
  set(body "// Generated from idl/ros/monocle_msgs by idl/record/embed_msgs.cmake.\n#pragma once\n#include <map>\n#include <string>\nnamespace monocle::record {\ninline const std::map<std::string, std::string> kMonocleMsgsFiles = {\n")
  foreach(f ${files})
    file(READ ${f} text)
    get_filename_component(name ${f} NAME_WE)
    get_filename_component(kind_dir ${f} DIRECTORY)
    get_filename_component(kind ${kind_dir} NAME)
    string(APPEND body "  {\"monocle_msgs/${kind}/${name}\", R\"msgdef(${text})msgdef\"},\n")
  endforeach()
  string(APPEND body "};\n}  // namespace monocle::record\n")
  # Written through a copy that changes the header only when its text changes (no rebuilds).
  file(WRITE ${out}.tmp "${body}")
  configure_file(${out}.tmp ${out} COPYONLY)
  set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${files})
endfunction()
