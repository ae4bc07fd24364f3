// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// The model database of the scene loop (thesis Secs. 3.1, 3.4): a directory with one subdirectory per model,
///
/// - `<dir>/<name>/mesh.ply`: the mesh (model frame, metres; binary PLY);
/// - `<dir>/<name>/ppf.bin`: its precomputed PPF feature table (ppf_model_io.hpp: versioned, checksummed);
/// - `<dir>/<name>/model.json`: metadata (format, version, name, size_m, date, source_scans, file names);
///
/// loaded at start and extended with newly modeled objects. An entry is written into `<dir>/.<name>.partial/`
/// (each file via a temporary file renamed into place), and that directory is renamed to `<dir>/<name>` last, so
/// an interrupted write never leaves a half entry: names starting with '.' (stale partial entries) and `*.tmp`
/// files are ignored by open() and a stale partial entry is replaced by the next add() of that name.

#include <algorithm>
#include <chrono>
#include <ctime>
#include <filesystem>
#include <string>
#include <system_error>
#include <vector>

#include <nlohmann/json.hpp>

#include "nbs/core/error.hpp"
#include "nbs/io/load_mesh.hpp"
#include "nbs/io/write_json.hpp"
#include "nbs/io/write_ply.hpp"
#include "nbs/mesh/indexed_mesh.hpp"
#include "nbs/recognition/ppf_model_io.hpp"

namespace nbs {

/// Metadata of a database model (model.json).
struct ModelMetadata {
  std::string name;                       ///< [A-Za-z0-9_-]+, the entry's directory name
  double size_m = 0.0;                    ///< diagonal of the mesh's bounding box, metres (set by add())
  std::string date;                       ///< when it was modeled, ISO 8601 UTC (add(): now if empty)
  std::vector<std::string> source_scans;  ///< the scans it was modeled from (e.g. session paths), free text
};

/// One model: metadata, mesh (model frame) and PPF description.
struct DatabaseModel {
  ModelMetadata metadata;
  IndexedMesh mesh;
  PpfModel features;
};

/// The models of a database directory, in name order. Thread-safety: const members may run concurrently; add()
/// needs exclusive access.
class ModelDatabase {
public:
  static constexpr int kFormatVersion = 1;

  /// Loads every entry of the existing directory `dir`. Throws FileError naming the directory if it does not
  /// exist, or naming the file of the first entry with a missing or malformed file (nothing is loaded then).
  [[nodiscard]] static ModelDatabase open(const std::filesystem::path& dir) {
    std::error_code ec;
    if (!std::filesystem::is_directory(dir, ec))
      throw FileError(detail::concat(dir.string(), ": model database directory does not exist"));
    std::vector<std::filesystem::path> entries;
    for (const auto& e : std::filesystem::directory_iterator(dir, ec))
      if (e.is_directory() && e.path().filename().string().front() != '.') entries.push_back(e.path());
    if (ec) throw FileError(detail::concat(dir.string(), ": cannot list the directory: ", ec.message()));
    std::sort(entries.begin(), entries.end());
    ModelDatabase db(dir);
    for (const auto& e : entries) db.models_.push_back(load_entry(e));
    return db;
  }

  /// Creates `dir` (and its parents) if needed and opens it.
  [[nodiscard]] static ModelDatabase create(const std::filesystem::path& dir) {
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec) throw FileError(detail::concat(dir.string(), ": cannot create the model database directory: ", ec.message()));
    return open(dir);
  }

  [[nodiscard]] const std::filesystem::path& directory() const { return dir_; }
  [[nodiscard]] const std::vector<DatabaseModel>& models() const { return models_; }
  /// The model named `name`, or nullptr.
  [[nodiscard]] const DatabaseModel* find(const std::string& name) const {
    for (const DatabaseModel& m : models_)
      if (m.metadata.name == name) return &m;
    return nullptr;
  }

  /// Adds a model: writes its entry (layout above; size_m from the mesh, date now if empty) and appends it. Throws
  /// InvalidArgument (nothing written) for an invalid name or mesh or a name already in the database, FileError
  /// naming the file if a write fails (no entry appears then).
  const DatabaseModel& add(ModelMetadata metadata, const IndexedMesh& mesh, PpfModel features) {
    check_name(metadata.name);
    mesh.validate();
    detail::require(find(metadata.name) == nullptr, "ModelDatabase::add: a model named '", metadata.name,
                    "' is already in ", dir_.string());
    Aabb box;
    for (const Vec3& v : mesh.vertices) box.extend(v);
    metadata.size_m = box.empty() ? 0.0 : (box.max - box.min).norm();
    if (metadata.date.empty()) metadata.date = utc_now();
    const std::filesystem::path final_dir = dir_ / metadata.name;
    const std::filesystem::path staging = dir_ / ("." + metadata.name + ".partial");
    std::error_code ec;
    detail::require(!std::filesystem::exists(final_dir, ec), "ModelDatabase::add: ", final_dir.string(),
                    " exists already");
    std::filesystem::remove_all(staging, ec);  // a stale partial entry of an interrupted add()
    std::filesystem::create_directory(staging, ec);
    if (ec) throw FileError(detail::concat(staging.string(), ": cannot create directory: ", ec.message()));
    try {
      write_ply((staging / kMesh).string(), mesh);
      write_ppf_model((staging / kFeatures).string(), features);
      write_json((staging / kMetadata).string(), to_json(metadata));
      std::filesystem::rename(staging, final_dir, ec);
      if (ec) throw FileError(detail::concat(final_dir.string(), ": cannot rename ", staging.string(),
                                             " into place: ", ec.message()));
    } catch (...) {
      std::error_code ignored;
      std::filesystem::remove_all(staging, ignored);
      throw;
    }
    models_.push_back({std::move(metadata), mesh, std::move(features)});
    return models_.back();
  }

  static constexpr const char* kMesh = "mesh.ply";
  static constexpr const char* kFeatures = "ppf.bin";
  static constexpr const char* kMetadata = "model.json";

  /// Throws InvalidArgument naming `name` unless it is 1 to 200 characters of [A-Za-z0-9_-].
  static void check_name(const std::string& name) {
    detail::require(!name.empty() && name.size() <= 200 &&
                        std::all_of(name.begin(), name.end(),
                                    [](char c) {
                                      return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') ||
                                             (c >= '0' && c <= '9') || c == '_' || c == '-';
                                    }),
                    "ModelDatabase: model name '", name, "' must be 1 to 200 characters of [A-Za-z0-9_-]");
  }

private:
  explicit ModelDatabase(std::filesystem::path dir) : dir_(std::move(dir)) {}

  [[nodiscard]] static std::string utc_now() {
    const std::time_t t = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
    std::tm utc{};
    gmtime_r(&t, &utc);
    char text[32];
    return std::string(text, std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &utc));
  }

  [[nodiscard]] static nlohmann::ordered_json to_json(const ModelMetadata& m) {
    nlohmann::ordered_json j;
    j["format"] = "nbs-model";
    j["version"] = kFormatVersion;
    j["name"] = m.name;
    j["size_m"] = m.size_m;
    j["date"] = m.date;
    j["source_scans"] = m.source_scans;
    j["mesh"] = kMesh;
    j["features"] = kFeatures;
    return j;
  }

  [[nodiscard]] static DatabaseModel load_entry(const std::filesystem::path& entry) {
    const std::string meta_path = (entry / kMetadata).string();
    ModelMetadata meta;
    try {
      const nlohmann::json j = nlohmann::json::parse(io_detail::read_file_bytes(meta_path));
      detail::require(j.value("format", std::string()) == "nbs-model", "\"format\" is not \"nbs-model\"");
      detail::require(j.at("version").get<int>() == kFormatVersion, "\"version\" ", j.at("version").dump(),
                      ", this build reads ", kFormatVersion);
      meta.name = j.at("name").get<std::string>();
      meta.size_m = j.at("size_m").get<double>();
      meta.date = j.at("date").get<std::string>();
      meta.source_scans = j.at("source_scans").get<std::vector<std::string>>();
      detail::require(j.at("mesh").get<std::string>() == kMesh && j.at("features").get<std::string>() == kFeatures,
                      "\"mesh\" and \"features\" must be \"", kMesh, "\" and \"", kFeatures, "\"");
      detail::require(meta.name == entry.filename().string(), "\"name\" '", meta.name,
                      "' differs from the directory name");
    } catch (const nlohmann::json::exception& e) {
      throw FileError(detail::concat(meta_path, ": malformed model metadata: ", e.what()));
    } catch (const InvalidArgument& e) {
      throw FileError(detail::concat(meta_path, ": malformed model metadata: ", e.what()));
    }
    const std::string mesh_path = (entry / kMesh).string();
    IndexedMesh mesh;
    try {
      mesh = load_mesh(mesh_path);
    } catch (const InvalidArgument& e) {
      throw FileError(detail::concat(mesh_path, ": ", e.what()));
    }
    return {std::move(meta), std::move(mesh), read_ppf_model((entry / kFeatures).string())};
  }

  std::filesystem::path dir_;
  std::vector<DatabaseModel> models_;
};

}  // namespace nbs
