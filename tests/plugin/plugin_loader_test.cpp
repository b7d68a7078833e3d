// Tests of PluginLoader against the good and deliberately broken plugins in test_plugins/.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

#include "core/plugin/plugin_loader.h"
#include "core/util/elf_check.h"
#include "core/util/error.h"
#include "core/util/shared_library.h"
#include "tests/support/error_text.h"
#include "test_plugin_interface.h"

namespace facetool {
namespace {

const std::string kPluginDir = FACETOOL_TEST_PLUGIN_DIR;

std::string plugin_file(const std::string& name) {
  return kPluginDir + "/" + name + FACETOOL_PLUGIN_FILE_SUFFIX;
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

using testing::error_text;

// A loader that searches only `dirs`, so the tests do not depend on the machine's plugins.
PluginLoader loader_over(std::vector<std::string> dirs) {
  PluginLoader loader;
  loader.set_search_dirs(std::move(dirs));
  return loader;
}

TEST(PluginLoader, KindNames) {
  EXPECT_STREQ(plugin_kind_name(FACETOOL_PLUGIN_NETWORK), "network");
  EXPECT_STREQ(plugin_kind_name(FACETOOL_PLUGIN_LOSS), "loss");
  EXPECT_STREQ(plugin_kind_name(FACETOOL_PLUGIN_RENDERER), "renderer");
  EXPECT_STREQ(plugin_kind_name(0), "unknown");
  EXPECT_STREQ(plugin_kind_name(99), "unknown");
}

TEST(PluginLoader, GoodPluginLoadsAndCreatesItsObject) {
  PluginLoader loader = loader_over({});
  const PluginInfo& info = loader.load_file(plugin_file("good_loss"));
  EXPECT_EQ(info.name, "test_loss");
  EXPECT_EQ(info.version, "1.2.3");
  EXPECT_EQ(info.kind, static_cast<uint32_t>(FACETOOL_PLUGIN_LOSS));
  EXPECT_EQ(info.description, "a loss plugin used by the plugin loader tests");
  EXPECT_EQ(info.path, plugin_file("good_loss"));
  ASSERT_NE(info.descriptor, nullptr);
  ASSERT_EQ(loader.plugins().size(), 1u);

  int destroyed = 0;
  {
    std::shared_ptr<Plugin> object = loader.create(loader.find(FACETOOL_PLUGIN_LOSS, "test_loss"));
    ASSERT_NE(object, nullptr);
    // The object's type crosses the library boundary: dynamic_cast must work on it.
    auto* typed = dynamic_cast<TestPluginInterface*>(object.get());
    ASSERT_NE(typed, nullptr);
    EXPECT_EQ(typed->answer(), 42);
    typed->set_destroyed_flag(&destroyed);
    EXPECT_EQ(destroyed, 0);
  }
  EXPECT_EQ(destroyed, 1) << "the plugin's destroy function did not run";
}

TEST(PluginLoader, LoadingTheSameFileTwiceKeepsOnePlugin) {
  PluginLoader loader = loader_over({});
  loader.load_file(plugin_file("good_loss"));
  loader.load_file(kPluginDir + "/./good_loss" FACETOOL_PLUGIN_FILE_SUFFIX);
  EXPECT_EQ(loader.plugins().size(), 1u);
}

TEST(PluginLoader, WrongApiVersionIsRefusedWithBothVersions) {
  PluginLoader loader = loader_over({});
  const std::string file = plugin_file("wrong_version");
  const std::string message = error_text([&] { loader.load_file(file); });
  EXPECT_TRUE(contains(message, file)) << message;
  EXPECT_TRUE(contains(message, "version " + std::to_string(FACETOOL_PLUGIN_API_VERSION + 1)))
      << message;
  EXPECT_TRUE(contains(message, "version " + std::to_string(FACETOOL_PLUGIN_API_VERSION)))
      << message;
  EXPECT_TRUE(contains(message, "rebuild")) << message;
  EXPECT_TRUE(loader.plugins().empty());
}

TEST(PluginLoader, OlderApiVersionIsRefusedWithBothVersions) {
  PluginLoader loader = loader_over({});
  const std::string file = plugin_file("old_version");
  const std::string message = error_text([&] { loader.load_file(file); });
  EXPECT_TRUE(contains(message, file)) << message;
  EXPECT_TRUE(contains(message, "API version " + std::to_string(FACETOOL_PLUGIN_API_VERSION - 1)))
      << message;
  EXPECT_TRUE(contains(message, "version " + std::to_string(FACETOOL_PLUGIN_API_VERSION)))
      << message;
  EXPECT_TRUE(loader.plugins().empty());
}

TEST(PluginLoader, AnotherCxxAbiIsRefusedWithBothAbis) {
  PluginLoader loader = loader_over({});
  const std::string file = plugin_file("other_abi");
  const std::string message = error_text([&] { loader.load_file(file); });
  EXPECT_TRUE(contains(message, file)) << message;
  EXPECT_TRUE(contains(message, "C++ ABI 'libc++'")) << message;
  EXPECT_TRUE(contains(message, "clang 99.0 (a test's pretence)")) << message;
  EXPECT_TRUE(contains(message, std::string("'") + FACETOOL_PLUGIN_CXX_ABI + "'")) << message;
  EXPECT_TRUE(loader.plugins().empty());
}

TEST(PluginLoader, RecordsTheCompilerOfAPlugin) {
  PluginLoader loader = loader_over({});
  const PluginInfo& info = loader.load_file(plugin_file("good_loss"));
  EXPECT_EQ(info.compiler, FACETOOL_PLUGIN_COMPILER);
}

TEST(PluginLoader, MissingFileIsAClearError) {
  PluginLoader loader = loader_over({});
  const std::string file = kPluginDir + "/does_not_exist" FACETOOL_PLUGIN_FILE_SUFFIX;
  const std::string message = error_text([&] { loader.load_file(file); });
  EXPECT_TRUE(contains(message, file)) << message;
  EXPECT_TRUE(contains(message, "does not exist")) << message;
}

TEST(PluginLoader, MissingEntryPointIsRefused) {
  PluginLoader loader = loader_over({});
  const std::string file = plugin_file("no_entry");
  const std::string message = error_text([&] { loader.load_file(file); });
  EXPECT_TRUE(contains(message, file)) << message;
  EXPECT_TRUE(contains(message, FACETOOL_PLUGIN_ENTRY_SYMBOL)) << message;
  EXPECT_TRUE(contains(message, "FACETOOL_DEFINE_PLUGIN")) << message;
}

TEST(PluginLoader, UnknownKindIsRefused) {
  PluginLoader loader = loader_over({});
  const std::string file = plugin_file("unknown_kind");
  const std::string message = error_text([&] { loader.load_file(file); });
  EXPECT_TRUE(contains(message, file)) << message;
  EXPECT_TRUE(contains(message, "unknown kind 99")) << message;
}

TEST(PluginLoader, DuplicateNameIsRefusedNamingBothFiles) {
  PluginLoader loader = loader_over({});
  const std::string first = plugin_file("good_loss");
  const std::string second = plugin_file("second_good_loss");
  loader.load_file(first);
  const std::string message = error_text([&] { loader.load_file(second); });
  EXPECT_TRUE(contains(message, "plugin name 'test_loss' from " + second +
                                    " is already provided by " + first))
      << message;
  ASSERT_EQ(loader.plugins().size(), 1u);
  EXPECT_EQ(loader.plugins()[0].version, "1.2.3");
}

TEST(PluginLoader, CreateReturningNullThrows) {
  PluginLoader loader = loader_over({});
  const PluginInfo& info = loader.load_file(plugin_file("null_create"));
  EXPECT_EQ(info.kind, static_cast<uint32_t>(FACETOOL_PLUGIN_RENDERER));
  const std::string message = error_text([&] { loader.create(info); });
  EXPECT_TRUE(contains(message, "null_create")) << message;
  EXPECT_TRUE(contains(message, "failed to create")) << message;
}

TEST(PluginLoader, NotALibraryIsRefusedWithTheLoaderMessage) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("facetool_plugin_test_" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  const std::string file = (dir / ("text" FACETOOL_PLUGIN_FILE_SUFFIX)).string();
  std::ofstream(file) << "this is not a shared library\n";

  PluginLoader loader = loader_over({dir.string()});
  const std::string message = error_text([&] { loader.load_file(file); });
  EXPECT_TRUE(contains(message, file)) << message;
  EXPECT_TRUE(contains(message, "not a loadable library")) << message;
  loader.discover();
  EXPECT_TRUE(loader.plugins().empty());
  ASSERT_EQ(loader.problems().size(), 1u);
  EXPECT_TRUE(contains(loader.problems()[0], file));
  std::filesystem::remove_all(dir);
}

TEST(PluginLoader, DiscoverLoadsTheGoodOnesAndReportsTheProblems) {
  // The folder is listed twice: files seen again are neither reloaded nor reported again.
  PluginLoader loader = loader_over({kPluginDir, kPluginDir});
  loader.discover();

  std::vector<std::string> names;
  for (const PluginInfo& info : loader.plugins()) names.push_back(info.name);
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names, (std::vector<std::string>{"null_create", "test_loss"}));

  const std::vector<std::string>& problems = loader.problems();
  ASSERT_EQ(problems.size(), 6u);
  for (const char* broken : {"no_entry", "second_good_loss", "unknown_kind", "wrong_version",
                             "old_version", "other_abi"}) {
    const std::string file = plugin_file(broken);
    const bool reported = std::any_of(problems.begin(), problems.end(), [&](const std::string& p) {
      return contains(p, file);
    });
    EXPECT_TRUE(reported) << broken << " was not reported";
  }

  // Discovering again changes nothing.
  loader.discover();
  EXPECT_EQ(loader.plugins().size(), 2u);
  EXPECT_EQ(loader.problems().size(), 6u);
}

TEST(PluginLoader, FindListsTheAvailablePlugins) {
  PluginLoader loader = loader_over({});
  loader.load_file(plugin_file("good_loss"));
  EXPECT_EQ(loader.find(FACETOOL_PLUGIN_LOSS, "test_loss").name, "test_loss");
  const std::string message =
      error_text([&] { loader.find(FACETOOL_PLUGIN_LOSS, "no_such_loss"); });
  EXPECT_TRUE(contains(message, "no_such_loss")) << message;
  EXPECT_TRUE(contains(message, "test_loss")) << message;
  // The right name but the wrong kind is not a match.
  EXPECT_THROW(loader.find(FACETOOL_PLUGIN_NETWORK, "test_loss"), Error);
}

TEST(PluginLoader, DefaultSearchDirsHonourTheEnvironment) {
  const char* old_value = std::getenv("FACETOOL_PLUGIN_PATH");
  const std::string saved = old_value ? old_value : "";
  setenv("FACETOOL_PLUGIN_PATH", "/first/dir::/second/dir", 1);
  const std::vector<std::string> dirs = PluginLoader::default_search_dirs();
  if (old_value)
    setenv("FACETOOL_PLUGIN_PATH", saved.c_str(), 1);
  else
    unsetenv("FACETOOL_PLUGIN_PATH");

  ASSERT_GE(dirs.size(), 4u);
  EXPECT_EQ(dirs[0], "/first/dir");
  EXPECT_EQ(dirs[1], "/second/dir");
  EXPECT_EQ(dirs[2], executable_dir());
  EXPECT_EQ(dirs[3], executable_dir() + "/../lib/facetool/plugins");
  EXPECT_EQ(PluginLoader().search_dirs(), PluginLoader::default_search_dirs());
}

// Regression for issue 10 (SIGBUS in dlopen): a plugin cut short at any size is refused with a
// message naming the file before the loader maps it; the complete copy still loads, and the
// same check guards backend modules (SharedLibrary::open is their only way in).
TEST(PluginLoader, TruncatedLibrariesAreRefusedBeforeDlopen) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() /
                                    ("facetool_truncated_plugin_" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  std::ifstream in(plugin_file("good_loss"), std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_GT(bytes.size(), 6000u);
  const std::string complete = (dir / ("complete" FACETOOL_PLUGIN_FILE_SUFFIX)).string();
  std::ofstream(complete, std::ios::binary) << bytes;
  EXPECT_NO_THROW(check_loadable_elf_file(complete));
  EXPECT_NO_THROW(loader_over({dir.string()}).load_file(complete));

  for (const size_t size : {size_t{0}, size_t{3}, size_t{63}, size_t{100}, size_t{3000},
                            bytes.size() / 2, bytes.size() - 1}) {
    const std::string file =
        (dir / ("cut_" + std::to_string(size) + FACETOOL_PLUGIN_FILE_SUFFIX)).string();
    std::ofstream(file, std::ios::binary) << bytes.substr(0, size);
    const std::string direct = error_text([&] { check_loadable_elf_file(file); });
    EXPECT_TRUE(contains(direct, file)) << direct;
    const std::string message = error_text([&] { loader_over({}).load_file(file); });
    EXPECT_TRUE(contains(message, file)) << size << " bytes: " << message;
    EXPECT_TRUE(contains(message, "truncated") || contains(message, "ELF header"))
        << size << " bytes: " << message;
  }
  // Not ELF at all, and a folder named like a plugin.
  const std::string text = (dir / ("text" FACETOOL_PLUGIN_FILE_SUFFIX)).string();
  std::ofstream(text) << "#!/bin/sh\necho this is a script renamed as a plugin, long enough "
                         "to hold an ELF header's worth of bytes\n";
  EXPECT_TRUE(contains(error_text([&] { check_loadable_elf_file(text); }), "no ELF magic"));
  const std::string folder = (dir / ("folder" FACETOOL_PLUGIN_FILE_SUFFIX)).string();
  std::filesystem::create_directories(folder);
  EXPECT_TRUE(contains(error_text([&] { check_loadable_elf_file(folder); }),
                       "not a regular file"));
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace facetool
