// Compiled OpenCL programs, cached in memory per process and as binaries on disk across runs.
#pragma once

#include <CL/cl.h>

#include <map>
#include <mutex>
#include <string>

#include "backends/opencl/opencl_context.h"

namespace facetool::opencl {

// The folder holding cached program binaries: $FACETOOL_CACHE_DIR, else
// $XDG_CACHE_HOME/facetool/opencl, else ~/.cache/facetool/opencl ("" when none can be found).
std::string default_program_cache_dir();

class ProgramCache {
 public:
  struct Stats {
    int memory_hits = 0;
    int disk_hits = 0;
    int compiles = 0;
  };

  // `cache_dir` empty disables the disk cache.
  ProgramCache(const Context& context, std::string cache_dir);
  ~ProgramCache();
  ProgramCache(const ProgramCache&) = delete;
  ProgramCache& operator=(const ProgramCache&) = delete;

  // The built program for `source` with `options`; `name` only labels errors. Throws
  // facetool::Error with the program name and the full build log when compilation fails.
  cl_program get(const std::string& name, const std::string& source, const std::string& options);

  Stats stats() const;
  const std::string& cache_dir() const { return cache_dir_; }
  // The file a program with these inputs is cached in (for tests).
  std::string cache_file(const std::string& source, const std::string& options) const;

 private:
  cl_program load_binary(const std::string& path, const std::string& options);
  cl_program compile(const std::string& name, const std::string& source,
                     const std::string& options);
  void store_binary(cl_program program, const std::string& path);

  const Context& context_;
  std::string cache_dir_;
  mutable std::mutex mutex_;
  std::map<std::string, cl_program> programs_;  // by options + '\0' + source
  Stats stats_;
};

}  // namespace facetool::opencl
