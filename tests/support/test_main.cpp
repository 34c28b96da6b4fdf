// The main() of every test binary: points the environment at this build (the podium binary, the
// plugin folder, ../shared) before running the tests, so tests behave the same under ctest, when
// run by hand, and in a debugger. Values already in the environment win.
#include <gtest/gtest.h>

#include <cstdlib>

int main(int argc, char** argv) {
  ::setenv("PODIUM_BIN", PODIUM_TEST_BIN, 0);
  ::setenv("PODIUM_PLUGIN_PATH", PODIUM_TEST_PLUGIN_DIR, 0);
  ::setenv("PODIUM_SHARED_DIR", PODIUM_TEST_SHARED_DIR, 0);
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
