// `facetool view`: a self-contained HTML page per decomposed photo, to look at and relight (docs/viewer.md).
#include <filesystem>
#include <iostream>

#include "apps/facetool/commands/command.h"
#include "apps/facetool/commands/command_options.h"
#include "libs/view/view_files.h"

namespace po = boost::program_options;
namespace fs = std::filesystem;

namespace facetool {
namespace {

int run_view(CommandContext&, const std::vector<std::string>& args) {
  po::options_description options("Options");
  options.add_options()
      ("feather", po::value<double>()->default_value(3.0), "the --feather infer was run with (crop pixels)")
      ("face-region", po::value<std::string>()->default_value("auto"),
       "the mask infer pasted with: hull, forehead, or auto (whichever reproduces photo.exr's coverage)")
      ("max-side", po::value<int>()->default_value(4096), "refuse photos larger than this many pixels a side (up to 8192)")
      ("no-index", "do not write index.html");
  po::options_description hidden;
  hidden.add_options()("folders", po::value<std::vector<std::string>>(), "infer output folders");
  po::positional_options_description positional;
  positional.add("folders", -1);
  po::variables_map values;
  if (!parse_command_options(
          "view OUT|OUT/PHOTO...",
          "Writes view.html into each photo folder of an infer run (OUT/<photo>/): one self-contained page\n"
          "(no server, no network) with the photo and its layers under a wipe, the landmarks, each face's\n"
          "light, and the faces relit in the browser (WebGL2) as `relight --mode render|ratio` relights\n"
          "them. Given infer's output folder OUT, it also writes OUT/index.html linking the pages. A\n"
          "folder that cannot be shown is reported and skipped; the exit status is then 1 (docs/viewer.md).",
          options, positional, args, values, hidden))
    return 0;
  check_option_ranges(values, {{"feather", 0, 100}, {"max-side", 16, 8192}});
  if (!values.count("folders")) throw UsageError("view: give infer's output folder (or photo folders in it)");
  view::ViewOptions view_options;
  view_options.feather = values["feather"].as<double>();
  view_options.max_side = values["max-side"].as<int>();
  const std::string region = values["face-region"].as<std::string>();
  if (region == "hull") view_options.mask = view::MaskShape::kHull;
  else if (region == "forehead") view_options.mask = view::MaskShape::kForehead;
  else if (region != "auto") throw UsageError("view: --face-region must be auto, hull or forehead; got '" + region + "'");

  int failed = 0, pages = 0;
  for (const std::string& path : values["folders"].as<std::vector<std::string>>()) {
    std::vector<std::string> folders;
    try {
      folders = view::photo_folders(path);
    } catch (const Error& e) {
      std::cerr << "view: " << e.what() << "\n";
      ++failed;
      continue;
    }
    // An index for a run's folder; a photo folder given alone gets its page only.
    const bool run_folder = folders.size() != 1 || folders[0] != path;
    const std::string index = run_folder && !values.count("no-index") ? (fs::path(path) / "index.html").string() : "";
    const int bad = view::write_view_pages(folders, index, view_options);
    failed += bad;
    pages += static_cast<int>(folders.size()) - bad;
    if (!index.empty() && bad < static_cast<int>(folders.size())) std::cerr << "index: " << index << "\n";
  }
  std::cerr << "wrote " << pages << " view page(s)" << (failed ? "; " + std::to_string(failed) + " failed (see above)" : "") << "\n";
  return failed > 0 ? 1 : 0;
}

const CommandRegistration registration{
    {"view", "write a self-contained HTML page per decomposed photo: its layers, and its faces relit in the browser", run_view}};

}  // namespace
}  // namespace facetool
