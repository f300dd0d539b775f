# Doxygen's input filter for include/toolpoint (docs/Doxyfile): the headers are commented with
# plain // lines, written for a reader of the header; this reads them as documentation without
# changing the files.
#   - the file's opening comment documents the file (\file);
#   - a // line on its own documents the declaration after it;
#   - a // after code on the same line (a member's unit, a default's meaning) documents that code.
1s#^// #/*! \\file */ /// #
s#^([[:space:]]*)//( |$)#\1///\2#
s#([;,{]|\))([[:space:]]+)//( )#\1\2///<\3#
