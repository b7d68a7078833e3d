// facetool's entry point: global options, dispatch to a subcommand, and error reporting.
#include <unistd.h>

#include <boost/program_options.hpp>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <new>
#include <string>
#include <vector>

#include "apps/facetool/allocator_tuning.h"
#include "apps/facetool/commands/command.h"
#include "apps/facetool/commands/command_options.h"
#include "core/backend/registry.h"
#include "core/util/atomic_file.h"
#include "core/util/error.h"
#include "core/util/memory_budget.h"
#include "core/util/terminal_text.h"

#ifndef FACETOOL_VERSION
#define FACETOOL_VERSION "unknown"
#endif

namespace po = boost::program_options;

namespace facetool {
namespace {

po::options_description global_only_options() {
  po::options_description options("Global options (before the command)");
  options.add_options()
      ("help,h", "show this help")
      ("version", "show facetool's version");
  return options;
}

void print_help(std::ostream& out) {
  out << "usage: facetool [options] <command> [command options]\n\n"
         "facetool estimates albedo, normals, SH visibility and SH light from a face photo.\n\n"
         "Commands:\n";
  size_t width = 0;
  for (const Command& command : all_commands()) width = std::max(width, command.name.size());
  for (const Command& command : all_commands())
    out << "  " << command.name << std::string(width - command.name.size() + 3, ' ')
        << command.summary << '\n';
  out << '\n' << global_only_options() << '\n' << common_options() << '\n'
      << "Run 'facetool <command> --help' for a command's options.\n";
}

// Index of the command name in `args`: the first token that is neither an option nor the value
// of an option that takes one.
size_t find_command_index(const std::vector<std::string>& args,
                          const po::options_description& options) {
  size_t i = 0;
  while (i < args.size()) {
    const std::string& token = args[i];
    if (token.size() < 2 || token[0] != '-') break;
    ++i;
    if (token.compare(0, 2, "--") == 0 && token.find('=') == std::string::npos) {
      const po::option_description* option = options.find_nothrow(token.substr(2), false);
      if (option && option->semantic()->max_tokens() > 0) ++i;
    }
  }
  return i;
}

// Copies the common options found in `values` into `context`.
void apply_common_options(const po::variables_map& values, CommandContext& context,
                          bool& backend_given) {
  if (values.count("backend")) {
    context.backend = values["backend"].as<std::string>();
    backend_given = true;
  }
  if (values.count("plugin"))
    for (const std::string& file : values["plugin"].as<std::vector<std::string>>())
      context.plugin_files.push_back(file);
  if (values.count("verbose") && values["verbose"].as<bool>()) context.verbose = true;
}

int run(const std::vector<std::string>& args, std::string& command_name) {
  po::options_description global = global_only_options();
  global.add(common_options());
  const size_t command_index = find_command_index(args, global);

  po::variables_map before;
  po::store(po::command_line_parser(std::vector<std::string>(args.begin(),
                                                             args.begin() + command_index))
                .options(global)
                .style(option_style())
                .run(),
            before);
  if (before.count("help")) {
    print_help(std::cout);
    return 0;
  }
  if (before.count("version")) {
    std::cout << "facetool " << FACETOOL_VERSION << '\n';
    return 0;
  }
  if (command_index == args.size()) {
    print_help(std::cerr);
    throw UsageError("no command given");
  }
  const Command& command = find_command(args[command_index]);
  command_name = command.name;

  // Common options may also follow the command name; everything else goes to the command.
  const std::vector<std::string> rest(args.begin() + command_index + 1, args.end());
  const po::options_description common = common_options();  // the parser keeps a reference
  const po::parsed_options parsed = po::command_line_parser(rest)
                                        .options(common)
                                        .style(option_style())
                                        .allow_unregistered()
                                        .run();
  po::variables_map after;
  po::store(parsed, after);

  CommandContext context;
  bool backend_given = false;
  apply_common_options(before, context, backend_given);
  apply_common_options(after, context, backend_given);
  // An explicitly chosen backend is checked up front so a typo fails before any work starts.
  if (backend_given) {
    Backend& backend = get_backend(context.backend);
    if (context.verbose)
      std::cerr << "facetool: backend " << context.backend << ": "
                << backend.device_description() << '\n';
  }
  return command.run(context, po::collect_unrecognized(parsed.options, po::include_positional));
}

// Messages may quote bytes of a hostile file: control bytes are shown, not sent to the terminal.
void print_error(const std::string& message) {
  std::cerr << "facetool: error: " << printable_text(message) << '\n';
}

// Ends a failed run at once after its message is out: no static destructors or library
// shutdown hooks, which after an exhausted allocation can wait forever (OpenBLAS's thread pool
// retrying mmap under ulimit -v). Every file a run writes is complete or removed by then.
[[noreturn]] void exit_now(int code) {
  std::cout.flush();
  std::cerr.flush();
  std::fflush(nullptr);
  ::_exit(code);
}

void print_usage_hint(const std::string& command_name) {
  if (command_name.empty())
    std::cerr << "Run 'facetool --help' for usage.\n";
  else
    std::cerr << "Run 'facetool " << command_name << " --help' for its options.\n";
}

}  // namespace
}  // namespace facetool

int main(int argc, char** argv) {
  // A file over the size limit (ulimit -f) fails its write with EFBIG, reported like a full disk,
  // instead of killing the process with its temporaries left; interrupted runs remove theirs.
  std::signal(SIGXFSZ, SIG_IGN);
  facetool::remove_temporaries_on_fatal_signals();
  facetool::enable_input_protection();  // no result replaces a photo, image or light this run read
  facetool::keep_freed_memory_for_reuse();
  std::string command_name;
  try {
    const int code = facetool::run(std::vector<std::string>(argv + 1, argv + argc), command_name);
    if (code != 0) facetool::exit_now(code);
    return 0;
  } catch (const facetool::UsageError& e) {
    facetool::print_error(e.what());
    facetool::print_usage_hint(command_name);
    facetool::exit_now(2);
  } catch (const po::error& e) {
    facetool::print_error(e.what());
    facetool::print_usage_hint(command_name);
    facetool::exit_now(2);
  } catch (const facetool::Error& e) {
    facetool::print_error(e.what());
    facetool::exit_now(1);
  } catch (const std::filesystem::filesystem_error& e) {
    // A folder walk or file test met a link loop, a permission or a vanished file: name it.
    facetool::print_error("cannot access '" + e.path1().string() + "': " + e.code().message() +
                          " (check the path, its links and permissions)");
    facetool::exit_now(1);
  } catch (const std::bad_alloc&) {
    facetool::print_error(
        facetool::out_of_memory("running '" + (command_name.empty() ? std::string("facetool")
                                                                     : command_name) + "'", 0)
            .what());
    facetool::exit_now(1);
  } catch (const std::exception& e) {
    facetool::print_error(std::string("unexpected failure: ") + e.what());
    facetool::exit_now(1);
  }
}
