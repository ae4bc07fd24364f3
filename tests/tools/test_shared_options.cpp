// SPDX-License-Identifier: BSD-3-Clause
// The option set every tool shares (tools/common/options.hpp), end to end: a bad value of a shared option exits 2
// with a message naming the option and the value and nothing on stdout, in each tool that is built; --config reads
// the long option names and rejects an unknown key; --help exits 0.

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "nbs_catch.hpp"
#include "nbs_temp_dir.hpp"
#include "nbs_read_file.hpp"

namespace fs = std::filesystem;

namespace {

struct Result {
  int code = -1;
  std::string out, err;
};

using nbs_test::slurp;

/// Runs `exe args` with stdout and stderr captured in files next to the test's temporary directory.
Result run(const std::string& exe, const std::string& args) {
  const fs::path dir = fs::temp_directory_path() / ("nbs_options_test_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string cmd = "'" + exe + "' " + args + " >'" + (dir / "out").string() + "' 2>'" + (dir / "err").string() + "'";
  const int status = std::system(cmd.c_str());
  Result r{WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(dir / "out"), slurp(dir / "err")};
  fs::remove_all(dir);
  return r;
}

/// The tools built with this configuration that take the mesh options.
std::vector<std::string> mesh_tools() {
  std::vector<std::string> t;
#ifdef NBS_MODEL_EXE
  t.emplace_back(NBS_MODEL_EXE);
#endif
#ifdef NBS_DIAGNOSE_EXE
  t.emplace_back(NBS_DIAGNOSE_EXE);
#endif
  return t;
}

}  // namespace

TEST_CASE("shared options: a bad value exits 2 naming the option and the value", "[tools][options]") {
  const std::vector<std::string> tools = mesh_tools();
  if (tools.empty()) {
    WARN("neither nbs_model nor nbs_diagnose is built (they need Embree): nothing to check");
    return;
  }
  const std::vector<std::pair<std::string, std::string>> bad = {
      {"--up w", "'w'"},          {"--size -0.1", "'-0.1'"},      {"--size 1e999", "'1e999'"},
      {"--seed 7x", "'7x'"},      {"--seed -1", "'-1'"},          {"--method C_X", "'C_X'"},
      {"--sensor nope", "'nope'"}, {"--sensor asus_xtion_pro", "area sensor"}, {"--size", "--size"}};
  for (const std::string& exe : tools) {
    for (const auto& [args, needle] : bad) {
      const Result r = run(exe, args);
      INFO(exe << " " << args << "\n" << r.err);
      CHECK(r.code == 2);
      CHECK(r.out.empty());
      CHECK_THAT(r.err, nbs_test::Contains(needle));
    }
    const Result help = run(exe, "--help");
    CHECK(help.code == 0);
    CHECK_THAT(help.out, nbs_test::Contains("--config"));
  }
}

TEST_CASE("nbs_model: bad --pose-error and --registration exit 2 naming the value", "[tools][options][pose_error]") {
#ifdef NBS_MODEL_EXE
  const std::vector<std::pair<std::string, std::string>> bad = {{"--pose-error 1", "'1'"},
                                                                {"--pose-error -1,0", "'-1,0'"},
                                                                {"--pose-error 1,nan", "'1,nan'"},
                                                                {"--registration gicp", "'gicp'"}};
  for (const auto& [args, needle] : bad) {
    const Result r = run(NBS_MODEL_EXE, args);
    INFO(args << "\n" << r.err);
    CHECK(r.code == 2);
    CHECK(r.out.empty());
    CHECK_THAT(r.err, nbs_test::Contains(needle));
    CHECK_THAT(r.err, nbs_test::Contains(args.substr(0, args.find(' '))));
  }
#else
  WARN("nbs_model is not built (it needs Embree): nothing to check");
#endif
}

TEST_CASE("nbs_model: a bad --robot exits 2 naming the path", "[tools][options][robot]") {
#ifdef NBS_MODEL_EXE
  for (const std::string path : {"/nonexistent/arm.urdf", NBS_DATA_DIR "/meshes/SOURCES.md"}) {
    const Result r = run(NBS_MODEL_EXE, "--robot " + path);
    INFO(r.err);
    CHECK(r.code == 2);
    CHECK_THAT(r.err, nbs_test::Contains("--robot"));
    CHECK_THAT(r.err, nbs_test::Contains(path));
  }
#else
  WARN("nbs_model is not built (it needs Embree): nothing to check");
#endif
}

TEST_CASE("nbs_model --color: coloured mesh.ply, mean colour error in report.json; without it no colour",
          "[tools][options][color]") {
#ifdef NBS_MODEL_EXE
  // A small mesh without colours (procedural checker), one scan: ≈ 1 s. The two checker colours are ≥ 0.65 apart
  // (color_distance), so a model coloured at random or black would be far above the bound; the split into vertices
  // near a colour edge and the rest must average to the mean.
  const nbs_test::TempDir tmp("nbs_color_test_");  // removed also when a REQUIRE fails
  const fs::path& dir = tmp.path;
  const std::string common = "--mesh '" NBS_DATA_DIR "/meshes/test-objects/mushroom.obj' --size 0.06 --scans 1 "
                             "--no-images --threads 1 --out '";
  Result r = run(NBS_MODEL_EXE, "--color " + common + (dir / "c").string() + "'");
  INFO(r.err);
  REQUIRE(r.code == 0);
  CHECK_THAT(r.out, nbs_test::Contains("colour  "));
  const auto js = nlohmann::json::parse(slurp(dir / "c" / "report.json"));
  const auto& fi = js.at("final");
  const double mean = fi.at("mean_color_error").get<double>();
  const auto n = fi.at("color_vertices").get<std::size_t>(), near = fi.at("color_near_edge_vertices").get<std::size_t>();
  CHECK(n == fi.at("mesh_vertices").get<std::size_t>());
  CHECK(n > 100);
  CHECK(mean > 0.0);
  CHECK(mean < 0.15);
  CHECK(near <= n);
  CHECK(mean * double(n) == Approx(fi.at("mean_color_error_near_edge").get<double>() * double(near) +
                                   fi.at("mean_color_error_rest").get<double>() * double(n - near)));
  CHECK_THAT(slurp(dir / "c" / "mesh.ply"), nbs_test::Contains("property uchar red"));

  r = run(NBS_MODEL_EXE, common + (dir / "plain").string() + "'");
  REQUIRE(r.code == 0);
  const auto plain = nlohmann::json::parse(slurp(dir / "plain" / "report.json"));
  CHECK_FALSE(plain.at("final").contains("mean_color_error"));
  CHECK(plain.at("final").at("mesh_vertices") == fi.at("mesh_vertices"));  // colour does not change the geometry
  const std::string plain_ply = slurp(dir / "plain" / "mesh.ply");
  CHECK_THAT(plain_ply.substr(0, plain_ply.find("end_header")), !nbs_test::Contains("red"));  // the header only
#else
  WARN("nbs_model is not built (it needs Embree): nothing to check");
#endif
}

TEST_CASE("shared options: --config", "[tools][options]") {
  const std::vector<std::string> tools = mesh_tools();
  if (tools.empty()) {
    WARN("neither nbs_model nor nbs_diagnose is built (they need Embree): nothing to check");
    return;
  }
  const fs::path cfg = fs::temp_directory_path() / ("nbs_options_cfg_" + std::to_string(::getpid()) + ".json");
  for (const std::string& exe : tools) {
    INFO(exe);
    std::ofstream(cfg) << R"({"up": "q"})";
    Result r = run(exe, "--config '" + cfg.string() + "'");
    CHECK(r.code == 2);
    CHECK_THAT(r.err, nbs_test::Contains("'q'"));
    std::ofstream(cfg) << R"({"upp": "z"})";
    r = run(exe, "--config '" + cfg.string() + "'");
    CHECK(r.code == 2);
    CHECK_THAT(r.err, nbs_test::Contains("unknown key 'upp'"));
    std::ofstream(cfg) << R"({"up": "q")";
    r = run(exe, "--config '" + cfg.string() + "'");
    CHECK(r.code == 2);
    CHECK_THAT(r.err, nbs_test::Contains("not valid JSON"));
    // The command line wins over the file: the bad file value is replaced, and the bad mesh is what is reported.
    std::ofstream(cfg) << R"({"up": "q", "mesh": "/nonexistent/m.obj"})";
    r = run(exe, "--config '" + cfg.string() + "' --up z");
    CHECK(r.code == 2);
    CHECK_THAT(r.err, nbs_test::Contains("/nonexistent/m.obj"));
    r = run(exe, "--config '" + (cfg.string() + ".missing") + "'");
    CHECK(r.code == 2);
    CHECK_THAT(r.err, nbs_test::Contains(".missing"));
  }
  fs::remove(cfg);
}
