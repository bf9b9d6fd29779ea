# Writes kerf's manual page, compressed: help2man turns `kerf --help` into the
# page, and every command's own --help (check, export, ... as listed under
# "Commands:" in the main help) becomes a section of it, so the page never
# drifts from the program.
#   cmake -DKERF=... -DHELP2MAN=... -DGZIP=... -DSUMMARY=... -DOUTPUT=kerf.1.gz -P ManPage.cmake
foreach(var KERF HELP2MAN GZIP SUMMARY OUTPUT)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "ManPage.cmake: ${var} is not set")
  endif()
endforeach()
# kerf may be a sanitizer build; its help needs no leak report.
set(ENV{ASAN_OPTIONS} detect_leaks=0)

function(run_help out)
  execute_process(COMMAND ${KERF} ${ARGN} --help RESULT_VARIABLE code OUTPUT_VARIABLE text ERROR_VARIABLE err)
  if(NOT code EQUAL 0)
    message(FATAL_ERROR "ManPage.cmake: `kerf ${ARGN} --help` failed (${code}): ${err}")
  endif()
  set(${out} "${text}" PARENT_SCOPE)
endfunction()

# Text as roff prints it verbatim: backslashes and minus signs escaped, and
# no line taken for a request.
function(roff_verbatim out text)
  string(REPLACE "\\" "\\e" text "${text}")
  string(REPLACE "-" "\\-" text "${text}")
  string(REGEX REPLACE "(^|\n)([.'])" "\\1\\\\&\\2" text "${text}")
  set(${out} "${text}" PARENT_SCOPE)
endfunction()

# The commands: the indented words under "Commands:" in the main help.
run_help(main_help)
string(REGEX MATCH "\nCommands:\n(.*)" commands_block "${main_help}")
string(REGEX REPLACE "\n\n.*" "" commands_block "${CMAKE_MATCH_1}")
string(REGEX MATCHALL "(^|\n)  [a-z]+ " command_lines "${commands_block}")
set(commands "")
foreach(line IN LISTS command_lines)
  string(STRIP "${line}" command)
  list(APPEND commands ${command})
endforeach()
if(NOT commands)
  message(FATAL_ERROR "ManPage.cmake: found no commands under \"Commands:\" in `kerf --help`")
endif()

set(include_text "[COMMANDS]\nEach command's own \\fB\\-\\-help\\fR:\n")
foreach(command IN LISTS commands)
  run_help(command_help ${command})
  roff_verbatim(command_help "${command_help}")
  string(APPEND include_text ".SS \"kerf ${command}\"\n.nf\n${command_help}.fi\n")
endforeach()
string(APPEND include_text [=[
[FILES]
.TP
.I share/kerf/examples
The bundled example parts (\fIside\-chair.kerf\fR, the default, and others),
found relative to the installed program: \fI/usr/share/kerf/examples\fR when
\fBkerf\fR is \fI/usr/bin/kerf\fR.
]=])

get_filename_component(work_dir "${OUTPUT}" DIRECTORY)
set(include_file "${work_dir}/kerf.h2m")
set(page "${work_dir}/kerf.1")
file(WRITE "${include_file}" "${include_text}")
execute_process(COMMAND ${HELP2MAN} --no-info --name=${SUMMARY} --include=${include_file} --output=${page} ${KERF}
  RESULT_VARIABLE code ERROR_VARIABLE err)
if(NOT code EQUAL 0)
  message(FATAL_ERROR "ManPage.cmake: help2man failed (${code}): ${err}")
endif()
# -n: no name or time stamp in the gzip header, so the page is reproducible.
execute_process(COMMAND ${GZIP} -9 -n -c ${page} OUTPUT_FILE ${OUTPUT}.tmp RESULT_VARIABLE code)
if(NOT code EQUAL 0)
  message(FATAL_ERROR "ManPage.cmake: gzip failed (${code})")
endif()
file(RENAME ${OUTPUT}.tmp ${OUTPUT})
