#pragma once
// A pool of read-only Queries connections: a request borrows one and gives it back when the
// lease ends. SQLite connections are not shared between threads; opening one per request would
// re-read the schema every time.
#include <filesystem>
#include <memory>
#include <mutex>
#include <vector>

#include "podium/store/queries.h"

namespace podium::web_dashboard {

class QueriesPool {
 public:
  explicit QueriesPool(std::filesystem::path database) : database_(std::move(database)) {
    idle_.push_back(store::Queries::open(database_));  // fails early on a bad database
  }

  class Lease {
   public:
    Lease(QueriesPool& pool, std::unique_ptr<store::Queries> q) : pool_(pool), q_(std::move(q)) {}
    ~Lease() { pool_.give_back(std::move(q_)); }
    Lease(const Lease&) = delete;
    Lease& operator=(const Lease&) = delete;
    store::Queries& operator*() const { return *q_; }
    store::Queries* operator->() const { return q_.get(); }

   private:
    QueriesPool& pool_;
    std::unique_ptr<store::Queries> q_;
  };

  Lease acquire() {
    {
      std::lock_guard lock(mutex_);
      if (!idle_.empty()) {
        auto q = std::move(idle_.back());
        idle_.pop_back();
        return Lease(*this, std::move(q));
      }
    }
    return Lease(*this, store::Queries::open(database_));
  }

 private:
  void give_back(std::unique_ptr<store::Queries> q) {
    std::lock_guard lock(mutex_);
    idle_.push_back(std::move(q));
  }

  std::filesystem::path database_;
  std::mutex mutex_;
  std::vector<std::unique_ptr<store::Queries>> idle_;
};

}  // namespace podium::web_dashboard
