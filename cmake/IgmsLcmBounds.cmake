# cmake -DHEADER=<generated .hpp> -P IgmsLcmBounds.cmake
# Bounds every length the sender controls in an lcm-gen C++ decoder, before
# it is used. LCM 1.3.1 resizes a vector to the length field's value before
# checking that the bytes are there (a length of 2^31 allocates 16 GB), and
# a string length of 0 becomes assign(ptr, -1), which throws. Each element
# takes at least one byte on the wire, so a length above the bytes left is a
# lie: decode returns -1 (undecodable), nothing is allocated. Fails the build
# if lcm-gen's output no longer has the shapes this patches.
cmake_policy(SET CMP0007 NEW)
file(READ "${HEADER}" text)
string(REGEX MATCHALL "\\.resize\\(" resizes "${text}")
list(LENGTH resizes n_resize)
string(REGEX REPLACE "([ \t]*)(this->[A-Za-z0-9_]+(\\[a[0-9]+\\])*)\\.resize\\(([^;]+)\\);"
       "\\1if ((\\4) < 0 || (\\4) > maxlen - pos) return -1;  // igms: bounded length\n\\1\\2.resize(\\4);"
       text "${text}")
string(REGEX MATCHALL "// igms: bounded length" guards "${text}")
list(LENGTH guards n_guards)
if(NOT n_guards EQUAL n_resize)
  message(FATAL_ERROR "${HEADER}: ${n_resize} resizes but ${n_guards} bounded: lcm-gen's output changed shape")
endif()
string(REGEX MATCHALL "(__[A-Za-z0-9_]+_len__|__elem_len) > maxlen - pos\\)" strings "${text}")
string(REGEX REPLACE "if\\((__[A-Za-z0-9_]+_len__|__elem_len) > maxlen - pos\\) return -1;"
       "if(\\1 <= 0 || \\1 > maxlen - pos) return -1;  // igms: no empty length (1.3.1 throws)" text "${text}")
string(REGEX MATCHALL "\\.assign\\(" assigns "${text}")
list(LENGTH strings n_strings)
list(LENGTH assigns n_assigns)
if(NOT n_strings EQUAL n_assigns)
  message(FATAL_ERROR "${HEADER}: ${n_assigns} string reads but ${n_strings} bounded: lcm-gen's output changed shape")
endif()
file(WRITE "${HEADER}" "${text}")
