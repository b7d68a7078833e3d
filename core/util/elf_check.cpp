// check_loadable_elf_file: reads the ELF and program headers and compares them with the size.
#include "core/util/elf_check.h"

#include <elf.h>
#include <sys/stat.h>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <vector>

#include "core/util/error.h"

namespace facetool {
namespace {

#if UINTPTR_MAX == 0xffffffffffffffffu
using ElfHeader = Elf64_Ehdr;
using ProgramHeader = Elf64_Phdr;
constexpr unsigned char kThisClass = ELFCLASS64;
#else
using ElfHeader = Elf32_Ehdr;
using ProgramHeader = Elf32_Phdr;
constexpr unsigned char kThisClass = ELFCLASS32;
#endif

#if defined(__x86_64__)
constexpr uint16_t kThisMachine = EM_X86_64;
#elif defined(__aarch64__)
constexpr uint16_t kThisMachine = EM_AARCH64;
#elif defined(__i386__)
constexpr uint16_t kThisMachine = EM_386;
#elif defined(__arm__)
constexpr uint16_t kThisMachine = EM_ARM;
#elif defined(__powerpc64__)
constexpr uint16_t kThisMachine = EM_PPC64;
#elif defined(__riscv)
constexpr uint16_t kThisMachine = EM_RISCV;
#elif defined(__s390x__)
constexpr uint16_t kThisMachine = EM_S390;
#else
constexpr uint16_t kThisMachine = EM_NONE;  // unknown: the machine is not compared
#endif

#if __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
constexpr unsigned char kThisByteOrder = ELFDATA2LSB;
#else
constexpr unsigned char kThisByteOrder = ELFDATA2MSB;
#endif

// True when [offset, offset + count * size) lies inside a file of `file_size` bytes.
bool inside(uint64_t offset, uint64_t count, uint64_t size, uint64_t file_size) {
  if (offset > file_size) return false;
  if (size != 0 && count > (file_size - offset) / size) return false;
  return true;
}

}  // namespace

void check_loadable_elf_file(const std::string& path) {
  auto bad = [&](const auto&... parts) {
    fail("cannot load '", path, "': ", parts...,
         "; the file is damaged or not a library for this machine: rebuild or reinstall it, or "
         "remove it from the folder searched");
  };
  struct stat info;
  if (::stat(path.c_str(), &info) != 0) fail("cannot load '", path, "': no such file");
  if (!S_ISREG(info.st_mode)) bad("it is not a regular file");
  const uint64_t file_size = static_cast<uint64_t>(info.st_size);
  std::ifstream in(path, std::ios::binary);
  if (!in) fail("cannot load '", path, "': cannot open it for reading (permissions?)");

  ElfHeader header;
  if (file_size < sizeof(header)) bad("it holds ", file_size, " bytes, less than an ELF header");
  in.read(reinterpret_cast<char*>(&header), sizeof(header));
  if (!in) bad("its ELF header cannot be read");
  if (std::memcmp(header.e_ident, ELFMAG, SELFMAG) != 0) bad("it is not an ELF file (no ELF magic)");
  if (header.e_ident[EI_CLASS] != kThisClass)
    bad("it is a ", header.e_ident[EI_CLASS] == ELFCLASS32 ? "32" : "64", "-bit ELF file");
  if (header.e_ident[EI_DATA] != kThisByteOrder) bad("its byte order is not this machine's");
  if (header.e_type != ET_DYN && header.e_type != ET_EXEC) bad("it is not a shared object");
  if (kThisMachine != EM_NONE && header.e_machine != kThisMachine)
    bad("it is built for another processor (ELF machine ", header.e_machine, ")");
  if (header.e_phentsize != sizeof(ProgramHeader) || header.e_phnum == 0)
    bad("it has no valid program header table");
  if (!inside(header.e_phoff, header.e_phnum, header.e_phentsize, file_size))
    bad("its program header table lies beyond the end of the file (", file_size,
        " bytes): the file is truncated");
  if (header.e_shnum != 0 && !inside(header.e_shoff, header.e_shnum, header.e_shentsize, file_size))
    bad("its section header table lies beyond the end of the file (", file_size,
        " bytes): the file is truncated");

  std::vector<ProgramHeader> segments(header.e_phnum);
  in.seekg(static_cast<std::streamoff>(header.e_phoff));
  in.read(reinterpret_cast<char*>(segments.data()),
          static_cast<std::streamsize>(segments.size() * sizeof(ProgramHeader)));
  if (!in) bad("its program header table cannot be read");
  bool loadable = false;
  for (const ProgramHeader& segment : segments) {
    if (segment.p_type != PT_LOAD) continue;
    loadable = true;
    if (!inside(segment.p_offset, 1, segment.p_filesz, file_size))
      bad("a loadable segment ends at byte ", segment.p_offset + segment.p_filesz,
          " beyond the end of the file (", file_size, " bytes): the file is truncated");
  }
  if (!loadable) bad("it has no loadable segment");
}

}  // namespace facetool
