#include "podium/plugins/loader.h"

#include <gtest/gtest.h>

#include <cstdlib>

#include "podium/base/error.h"
#include "process.h"

namespace podium::plugins {
namespace {

std::filesystem::path plugin_dir() { return std::getenv("PODIUM_PLUGIN_PATH"); }

std::string load_error(const std::function<void()>& fn) {
  try {
    fn();
  } catch (const base::UserError& e) {
    return e.what();
  }
  return "";
}

TEST(PluginLoader, LoadsLandscapeAndDescribesIt) {
  auto task = load_task("landscape");
  const auto d = task->describe(Json::object());
  EXPECT_EQ(d["params"].size(), 3u);
  EXPECT_EQ(d["features"].size(), 2u);
  EXPECT_TRUE(d["presets"].contains("smoke"));
}

TEST(PluginLoader, MissingPluginNamesFileAndFolders) {
  const auto error = load_error([] { load_task("no_such_task"); });
  EXPECT_NE(error.find("no file libpodium_task_no_such_task.so in"), std::string::npos) << error;
  EXPECT_NE(error.find(plugin_dir().string()), std::string::npos) << error;
}

TEST(PluginLoader, WrongAbiSaysBuiltForAndAccepted) {
  const auto error = load_error([] { load_task("landscape_wrong_abi"); });
  EXPECT_NE(error.find("plugin ABI version 999"), std::string::npos) << error;
  EXPECT_NE(error.find("this host accepts ABI version " + std::to_string(kAbiVersion)), std::string::npos) << error;
}

TEST(PluginLoader, LibraryWithoutSymbolsIsNotAPlugin) {
  podium::testing::TempDir dir;
  // Any shared library that is not a plugin: copy the wrong-ABI plugin's neighbour, libm.
  const auto fake = dir / "libpodium_task_fake.so";
  std::filesystem::copy_file("/lib/x86_64-linux-gnu/libm.so.6", fake);
  const auto error = load_error([&] { load_task_file(fake, "fake"); });
  EXPECT_NE(error.find("not a Podium task plugin (missing symbol podium_task_descriptor)"), std::string::npos) << error;
}

TEST(PluginLoader, GarbageFileIsOneLineError) {
  podium::testing::TempDir dir;
  const auto fake = dir / "libpodium_task_garbage.so";
  podium::testing::write_file(fake, "not an ELF file");
  const auto error = load_error([&] { load_task_file(fake, "garbage"); });
  EXPECT_NE(error.find("cannot load plugin"), std::string::npos) << error;
  EXPECT_EQ(error.find('\n'), std::string::npos);
}

}  // namespace
}  // namespace podium::plugins
