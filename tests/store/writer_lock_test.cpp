// The single-writer lock (store/writer_lock.h): one holder per database file, whatever path
// reaches it, released with its holder.
#include "podium/store/writer_lock.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "podium/base/error.h"
#include "podium/store/store.h"
#include "process.h"

namespace podium::store {
namespace {

namespace fs = std::filesystem;
using podium::testing::TempDir;

TEST(WriterLock, IsHeldThroughEveryPathToTheFileAndReleasedWithItsHolder) {
  TempDir dir;
  Store::open(dir / "p.db", Store::Access::read_write);
  fs::create_directories(dir / "sub");
  fs::create_symlink(dir / "p.db", dir / "sub/symlink.db");
  fs::create_hard_link(dir / "p.db", dir / "hard.db");
  EXPECT_FALSE(WriterLock::held(dir / "p.db"));
  {
    const WriterLock lock(dir / "p.db");
    for (const char* other : {"p.db", "sub/symlink.db", "hard.db"}) {
      EXPECT_TRUE(WriterLock::held(dir / other)) << other;
      EXPECT_THROW(WriterLock second(dir / other), base::RuntimeError) << other;
    }
  }
  EXPECT_FALSE(WriterLock::held(dir / "hard.db"));
  const WriterLock again(dir / "sub/symlink.db");
  EXPECT_TRUE(WriterLock::held(dir / "p.db"));
}

TEST(WriterLock, SqliteReadsAndWritesAreNotBlockedByIt) {
  TempDir dir;
  auto store = Store::open(dir / "p.db", Store::Access::read_write);
  const WriterLock lock(dir / "p.db");
  const auto id = store->add_campaign("c", Json::object(), 1, "", {});
  store->transaction([&] { store->add_event(id, "e", Json::object()); });
  EXPECT_EQ(Store::open(dir / "p.db", Store::Access::read_only)->campaigns().size(), 1u);
}

TEST(WriterLock, AMissingDatabaseIsOneClearError) {
  TempDir dir;
  try {
    WriterLock lock(dir / "none.db");
    FAIL() << "no error";
  } catch (const base::RuntimeError& e) {
    EXPECT_NE(std::string(e.what()).find("none.db"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace podium::store
