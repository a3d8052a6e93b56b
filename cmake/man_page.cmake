# suite.1 from `suite --help` and `suite --version` (CLI11's own text, as troff): run by the build
# once the program exists (in a cross build, under EMULATOR: qemu-user).
#   cmake -DSUITE=path/to/suite [-DEMULATOR=qemu-aarch64-static] -DOUT=suite.1 -P man_page.cmake
execute_process(COMMAND ${EMULATOR} ${SUITE} --help OUTPUT_VARIABLE help RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "${SUITE} --help failed (${rc})")
endif()
execute_process(COMMAND ${EMULATOR} ${SUITE} --version OUTPUT_VARIABLE version)
string(REGEX MATCH "^[^\n]*" first "${version}")
string(REGEX REPLACE "^suite ([^ ]+).*" "\\1" number "${first}")
# troff: a backslash is written \e; a line may not start with '.' or '\''.
string(REPLACE "\\" "\\e" help "${help}")
string(REGEX REPLACE "\n([.'])" "\n\\\\&\\1" help "\n${help}")
file(WRITE ${OUT} ".TH SUITE 1 \"\" \"suite ${number}\" \"User Commands\"
.SH NAME
suite \\- NUMA/cache micro-benchmarks with verified results
.SH SYNOPSIS
.B suite
[\\fICOMMAND\\fR] [\\fIOPTIONS\\fR]
.SH DESCRIPTION
What \\fBsuite \\-\\-help\\fR prints; each command has its own (\\fBsuite\\fR \\fICOMMAND\\fR \\fB\\-\\-help\\fR).
.PP
.nf
${help}
.fi
.SH VERSION
.nf
${version}.fi
")
