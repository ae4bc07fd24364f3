// SPDX-License-Identifier: BSD-3-Clause
// Flush folders of a killed process: the next backend's first flush removes them; a live owner's folder (in this
// process or another) is never removed. POSIX only (fork + SIGKILL).
#include "nbs_catch.hpp"
#include "nbs_temp_dir.hpp"

#if defined(__unix__)
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "nbs/space/hashed_block_backend.hpp"
#include "nbs/space/thesis_model.hpp"

namespace {
namespace fs = std::filesystem;
using Backend = nbs::HashedBlockBackend<nbs::ThesisState>;

struct StaleTempDir : nbs_test::TempDir {
  StaleTempDir() : nbs_test::TempDir("nbs_test_stale_") {}
};

std::vector<fs::path> block_folders(const fs::path& dir) {
  std::vector<fs::path> out;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().filename().string().rfind("nbs-blocks-", 0) == 0) out.push_back(e.path());
  return out;
}

nbs::ThesisState marked(int surf) {
  nbs::ThesisState s;
  s.surf = static_cast<decltype(s.surf)>(surf);
  s.free = -3;
  return s;
}

// Forks a child that flushes one block into dir, then kills itself with SIGKILL (no destructor runs).
void killed_child_flush(const fs::path& dir) {
  const pid_t pid = ::fork();
  REQUIRE(pid >= 0);
  if (pid == 0) {
    Backend b(0.01);
    b.set_flush_policy({.directory = dir});
    b.set({4, 5, 6}, marked(9));
    if (b.flush_all() != 1) ::_exit(3);
    ::raise(SIGKILL);
    ::_exit(4);  // not reached
  }
  int status = 0;
  REQUIRE(::waitpid(pid, &status, 0) == pid);
  REQUIRE(WIFSIGNALED(status));
  REQUIRE(WTERMSIG(status) == SIGKILL);
}
}  // namespace

TEST_CASE("a killed process's flush folder is removed at the next start; live owners' folders are kept",
          "[space][flush][stale]") {
  StaleTempDir dir;
  killed_child_flush(dir.path);
  const std::vector<fs::path> left = block_folders(dir.path);
  REQUIRE(left.size() == 1);  // what the killed process left behind
  REQUIRE(fs::exists(left[0] / "owner.lock"));
  const fs::path stale = left[0];

  Backend live(0.01);
  live.set_flush_policy({.directory = dir.path});
  live.set({1, 2, 3}, marked(7));
  REQUIRE(live.flush_all() == 1);
  CHECK(live.flush_stats().stale_folders_removed == 1);
  CHECK_FALSE(fs::exists(stale));
  REQUIRE(block_folders(dir.path) == std::vector<fs::path>{live.flush_folder()});

  // A second backend of this process, and a child process, must not remove the live backend's folder.
  Backend other(0.01);
  other.set_flush_policy({.directory = dir.path});
  other.set({1, 2, 3}, marked(2));
  REQUIRE(other.flush_all() == 1);
  CHECK(other.flush_stats().stale_folders_removed == 0);
  killed_child_flush(dir.path);  // its first flush sees two live folders and removes none
  CHECK(fs::exists(live.flush_folder()));
  CHECK(fs::exists(other.flush_folder()));
  CHECK(live.get({1, 2, 3}) == marked(7));  // reloaded from its folder
  CHECK(other.get({1, 2, 3}) == marked(2));
  CHECK(block_folders(dir.path).size() == 3);  // two live, one of the second killed child

  // A folder without owner.lock (being created, or not a backend's) is never touched.
  const fs::path foreign = dir.path / "nbs-blocks-foreign";
  fs::create_directories(foreign);
  Backend third(0.01);
  third.set_flush_policy({.directory = dir.path});
  third.set({0, 0, 0}, marked(1));
  REQUIRE(third.flush_all() == 1);
  CHECK(third.flush_stats().stale_folders_removed == 1);  // the second child's
  CHECK(fs::exists(foreign));
  CHECK(block_folders(dir.path).size() == 4);  // live, other, third, foreign
}
#endif
