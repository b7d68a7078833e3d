// -o / --output (alias --out) for every command that writes files.
#include "apps/facetool/commands/output_option.h"

#include <filesystem>

#include "apps/facetool/commands/command.h"

namespace po = boost::program_options;

namespace facetool {

void add_output_option(po::options_description& options, po::options_description& hidden,
                       std::string* target, const std::string& value_name,
                       const std::string& description) {
  options.add_options()("output,o", po::value(target)->value_name(value_name),
                        (description + " (--out is accepted too)").c_str());
  hidden.add_options()("out", po::value(target)->value_name(value_name), "alias of --output");
}

void check_output_option(const po::variables_map& values, const std::string& command,
                         const std::string& what) {
  const size_t given = values.count("output") + values.count("out");
  if (given > 1) throw UsageError(command + ": give -o/--output (or --out) only once");
  if (given == 0) throw UsageError(command + ": give " + what);
}

void check_output_file_location(const std::string& file, const std::string& option) {
  namespace fs = std::filesystem;
  std::error_code ec;
  check(!file.empty(), option, ": the file name is empty");
  check(!fs::is_directory(file, ec), option, " '", file,
        "' is a folder; give a file name inside it");
  const fs::file_status status = fs::status(file, ec);
  check(!fs::exists(status) || fs::is_regular_file(status), option, " '", file,
        "' is not a regular file (a device, a pipe or a socket): facetool writes its results only as new files or "
        "over regular files; give another name");
  const fs::path folder = fs::path(file).parent_path().empty() ? fs::path(".")
                                                               : fs::path(file).parent_path();
  check(fs::is_directory(folder, ec), option, " '", file, "': the folder '", folder.string(),
        "' does not exist; create it first");
}

}  // namespace facetool
