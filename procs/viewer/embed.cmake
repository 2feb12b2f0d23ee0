# cmake -DIN=page.html -DOUT=page.cpp -P embed.cmake: the page as a C++ string (one source of
# truth for the HTML/JS, edited as a normal file).
file(READ ${IN} content)
string(FIND "${content}" ")ucon_page\"" clash)
if(NOT clash EQUAL -1)
  message(FATAL_ERROR "${IN} contains the raw-string delimiter )ucon_page\"")
endif()
file(WRITE ${OUT}.tmp
  "// Generated from procs/viewer/page/viewer.html by procs/viewer/embed.cmake. Do not edit.\n"
  "namespace ucon {\nnamespace viewer {\nnamespace detail {\n"
  "extern const char kViewerPage[];\n"
  "const char kViewerPage[] = R\"ucon_page(${content})ucon_page\";\n"
  "}  // namespace detail\n}  // namespace viewer\n}  // namespace ucon\n")
execute_process(COMMAND ${CMAKE_COMMAND} -E copy_if_different ${OUT}.tmp ${OUT})
file(REMOVE ${OUT}.tmp)
