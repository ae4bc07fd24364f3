// SPDX-License-Identifier: BSD-3-Clause
// The model database: round trip, a corrupted feature table, missing and malformed files, an interrupted write.
#include "nbs_catch.hpp"

#include <fstream>

#include "nbs/recognition/model_database.hpp"
#include "nbs/sim/surface_samples.hpp"
#include "../nbs_temp_dir.hpp"
#include "../sim/test_meshes.hpp"

using namespace nbs;
using namespace nbs::test;
namespace fs = std::filesystem;

namespace {
PpfModel features_of(const IndexedMesh& m) { return PpfModel(oriented_points(sample_surface(m, 3000, 1))); }

void write_text(const fs::path& p, const std::string& text) { std::ofstream(p, std::ios::binary) << text; }

std::string read_text(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}
}  // namespace

TEST_CASE("ModelDatabase: round trip of mesh, feature table and metadata", "[recognition]") {
  const nbs_test::TempDir tmp("nbs_model_db_");
  const fs::path dir = tmp.path / "db";
  const IndexedMesh box = box_mesh(Vec3(0, 0, 0), Vec3(0.1, 0.06, 0.04));
  const IndexedMesh ball = uv_sphere(Vec3(0, 0, 0.05), 0.05, 8, 16);
  {
    ModelDatabase db = ModelDatabase::create(dir);
    CHECK(db.models().empty());
    db.add({"box", 0.0, "2026-01-02T03:04:05Z", {"session-1", "session-2"}}, box, features_of(box));
    const DatabaseModel& b = db.add({"ball", 0.0, "", {}}, ball, features_of(ball));
    CHECK(b.metadata.date.size() == 20);  // filled in: YYYY-MM-DDTHH:MM:SSZ
    CHECK_THROWS_WITH(db.add({"box", 0, "", {}}, box, features_of(box)), Catch::Contains("already in"));
    CHECK_THROWS_WITH(db.add({"../x", 0, "", {}}, box, features_of(box)), Catch::Contains("'../x'"));
    CHECK(db.models().size() == 2);
  }
  const ModelDatabase db = ModelDatabase::open(dir);
  REQUIRE(db.models().size() == 2);
  CHECK(db.models()[0].metadata.name == "ball");  // name order
  const DatabaseModel* b = db.find("box");
  REQUIRE(b);
  CHECK(b->metadata.size_m == Approx(std::sqrt(0.01 + 0.0036 + 0.0016)));
  CHECK(b->metadata.date == "2026-01-02T03:04:05Z");
  CHECK(b->metadata.source_scans == std::vector<std::string>{"session-1", "session-2"});
  CHECK(b->mesh.vertices == box.vertices);
  CHECK(b->mesh.triangles == box.triangles);
  const PpfModel::Table a = features_of(box).table(), r = b->features.table();
  CHECK(r.diameter_m == a.diameter_m);
  CHECK(r.points.points == a.points.points);
  CHECK(r.points.normals == a.points.normals);
  CHECK(r.keys == a.keys);
  CHECK(r.offsets == a.offsets);
  REQUIRE(r.entries.size() == a.entries.size());
  for (std::size_t k = 0; k < a.entries.size(); ++k)
    REQUIRE((r.entries[k].reference == a.entries[k].reference && r.entries[k].alpha == a.entries[k].alpha));
  // The restored table answers queries as the built one.
  for (std::size_t b2 = 0; b2 < a.keys.size(); b2 += 7)
    CHECK(b->features.find(a.keys[b2]).size() == a.offsets[b2 + 1] - a.offsets[b2]);
}

TEST_CASE("ModelDatabase: a corrupted table, missing or malformed files and a missing directory name the file",
          "[recognition]") {
  const nbs_test::TempDir tmp("nbs_model_db_");
  const IndexedMesh box = box_mesh(Vec3(0, 0, 0), Vec3(0.1, 0.06, 0.04));
  ModelDatabase::create(tmp.path).add({"box", 0, "", {}}, box, features_of(box));
  const fs::path table = tmp.path / "box" / "ppf.bin";
  const std::string good = read_text(table);
  CHECK_NOTHROW(ModelDatabase::open(tmp.path));

  std::string bad = good;
  bad[bad.size() / 2] ^= 0x10;  // one flipped bit
  write_text(table, bad);
  CHECK_THROWS_WITH(ModelDatabase::open(tmp.path), Catch::Contains(table.string()) && Catch::Contains("checksum"));
  write_text(table, good.substr(0, good.size() - 9));
  CHECK_THROWS_WITH(ModelDatabase::open(tmp.path), Catch::Contains(table.string()) && Catch::Contains("bytes"));
  bad = good;
  bad[8] = 2;  // version 2
  write_text(table, bad);
  CHECK_THROWS_WITH(ModelDatabase::open(tmp.path), Catch::Contains("format version 2"));
  write_text(table, "PLY nonsense");
  CHECK_THROWS_WITH(ModelDatabase::open(tmp.path), Catch::Contains("bad magic"));
  fs::remove(table);
  CHECK_THROWS_WITH(ModelDatabase::open(tmp.path), Catch::Contains(table.string()) && Catch::Contains("cannot open"));
  write_text(table, good);

  const fs::path meta = tmp.path / "box" / "model.json";
  const std::string good_meta = read_text(meta);
  write_text(meta, "{\"format\": \"nbs-model\", \"version\": 1, \"name\": \"box\"");
  CHECK_THROWS_WITH(ModelDatabase::open(tmp.path), Catch::Contains(meta.string()) && Catch::Contains("malformed"));
  write_text(meta, good_meta);
  fs::remove(tmp.path / "box" / "mesh.ply");
  CHECK_THROWS_WITH(ModelDatabase::open(tmp.path), Catch::Contains((tmp.path / "box" / "mesh.ply").string()));
  CHECK_THROWS_WITH(ModelDatabase::open(tmp.path / "nothing"), Catch::Contains("does not exist"));
}

TEST_CASE("ModelDatabase: an interrupted write never yields a half entry", "[recognition]") {
  const nbs_test::TempDir tmp("nbs_model_db_");
  const IndexedMesh box = box_mesh(Vec3(0, 0, 0), Vec3(0.1, 0.06, 0.04));
  ModelDatabase::create(tmp.path).add({"box", 0, "", {}}, box, features_of(box));
  // What an add() of "ball" killed half-way leaves: its staging directory with the mesh and a half-written
  // metadata temporary; and a stale temporary beside a complete entry's table.
  fs::create_directory(tmp.path / ".ball.partial");
  fs::copy_file(tmp.path / "box" / "mesh.ply", tmp.path / ".ball.partial" / "mesh.ply");
  write_text(tmp.path / ".ball.partial" / "model.json.tmp", "{\"format\": \"nbs-mo");
  write_text(tmp.path / "box" / "ppf.bin.tmp", "half a table");
  ModelDatabase db = ModelDatabase::open(tmp.path);
  REQUIRE(db.models().size() == 1);
  CHECK(db.models()[0].metadata.name == "box");
  CHECK(db.find("ball") == nullptr);
  // The next add() of that name replaces the stale staging directory.
  const IndexedMesh ball = uv_sphere(Vec3(0, 0, 0.05), 0.05, 8, 16);
  db.add({"ball", 0, "", {}}, ball, features_of(ball));
  CHECK(!fs::exists(tmp.path / ".ball.partial"));
  CHECK(ModelDatabase::open(tmp.path).models().size() == 2);
}
