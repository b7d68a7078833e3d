// A shared library's file checked before dlopen: a damaged one must give a message, not SIGBUS.
#pragma once

#include <string>

namespace facetool {

// Throws facetool::Error naming `path` unless it is a regular file holding an ELF shared object
// (or executable) for this process's class, byte order and machine whose program and section
// header tables and every PT_LOAD segment lie inside the file. The loader maps segments beyond
// the end of a truncated file and faults (SIGBUS) when touching them; this refuses such files.
void check_loadable_elf_file(const std::string& path);

}  // namespace facetool
