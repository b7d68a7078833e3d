// Replays stored inputs (seed corpus and regression files) through one fuzz target without
// libFuzzer: the test suite's guard that every input once found stays handled.
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

// Usage: <replayer> DIR...  Runs every regular file in each DIR (not recursive); fails when none
// was found, so that a moved corpus cannot make the test pass vacuously.
int main(int argc, char** argv) {
  namespace fs = std::filesystem;
  int count = 0;
  for (int a = 1; a < argc; ++a) {
    if (!fs::is_directory(argv[a])) continue;
    std::vector<fs::path> files;
    for (const auto& entry : fs::directory_iterator(argv[a]))
      if (entry.is_regular_file()) files.push_back(entry.path());
    for (const fs::path& file : files) {
      std::ifstream in(file, std::ios::binary);
      std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)),
                                 std::istreambuf_iterator<char>());
      std::printf("replay: %s (%zu bytes)\n", file.string().c_str(), bytes.size());
      std::fflush(stdout);
      LLVMFuzzerTestOneInput(bytes.data(), bytes.size());
      ++count;
    }
  }
  std::printf("replay: %d inputs handled\n", count);
  if (count == 0) std::fprintf(stderr, "replay: no input files found in the given folders\n");
  return count > 0 ? 0 : 1;
}
