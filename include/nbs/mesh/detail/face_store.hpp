#pragma once
/// \file
/// Triangles with vertex→face adjacency. The directed edges of Fig. 3.9 are read off the faces: a face (a, b, c) is
/// counter-clockwise around the normal, so it is the left triangle of a→b, b→c and c→a.
/// Invariant kept by every caller: a directed edge belongs to at most one face (hence an undirected edge to at most
/// two, with consistent orientation). Not thread-safe.

#include <array>
#include <cstdint>
#include <vector>

#include "nbs/mesh/mesh_concept.hpp"

namespace nbs::detail {

class FaceStore {
public:
  using Face = std::array<VertexId, 3>;
  static constexpr std::uint32_t kNoFace = 0xFFFFFFFFu;

  void add_vertex() {
    faces_of_.emplace_back();
    version_.push_back(0);
  }
  [[nodiscard]] std::size_t face_count() const { return faces_.size(); }
  [[nodiscard]] const Face& face(std::uint32_t f) const { return faces_[f]; }
  [[nodiscard]] std::uint32_t face_scan(std::uint32_t f) const { return scan_of_[f]; }
  [[nodiscard]] const std::vector<std::uint32_t>& faces_of(VertexId v) const { return faces_of_[v]; }
  [[nodiscard]] bool has_faces(VertexId v) const { return !faces_of_[v].empty(); }
  /// Changes whenever a face of v is added, replaced or reordered in faces_of(v) (wraps after 2^32 changes).
  [[nodiscard]] std::uint32_t version(VertexId v) const { return version_[v]; }

  /// Adds face (a, b, c); the caller guarantees the directed edges are free.
  std::uint32_t add(VertexId a, VertexId b, VertexId c, std::uint32_t scan) {
    const auto f = static_cast<std::uint32_t>(faces_.size());
    faces_.push_back({a, b, c});
    scan_of_.push_back(scan);
    for (VertexId v : {a, b, c}) {
      faces_of_[v].push_back(f);
      ++version_[v];
    }
    return f;
  }

  /// Replaces face f by (a, b, c), updating adjacency; the caller guarantees the directed edges are free.
  void replace(std::uint32_t f, VertexId a, VertexId b, VertexId c, std::uint32_t scan) {
    for (VertexId v : faces_[f]) {
      erase_from(faces_of_[v], f);
      ++version_[v];
    }
    faces_[f] = {a, b, c};
    scan_of_[f] = scan;
    for (VertexId v : faces_[f]) {
      faces_of_[v].push_back(f);
      ++version_[v];
    }
  }

  /// Face containing the directed edge a→b, or kNoFace.
  [[nodiscard]] std::uint32_t face_with(VertexId a, VertexId b) const {
    for (std::uint32_t f : faces_of_[a]) {
      const Face& t = faces_[f];
      if ((t[0] == a && t[1] == b) | (t[1] == a && t[2] == b) | (t[2] == a && t[0] == b)) return f;
    }
    return kNoFace;
  }

  /// Vertex closing the triangle on the left of a→b, or kNoVertex.
  [[nodiscard]] VertexId left_vertex(VertexId a, VertexId b) const {
    const std::uint32_t f = face_with(a, b);
    return f == kNoFace ? kNoVertex : opposite(f, a, b);
  }

  /// True if a and b share a face (in either direction).
  [[nodiscard]] bool has_edge(VertexId a, VertexId b) const {
    for (std::uint32_t f : faces_of_[a]) {
      const Face& t = faces_[f];
      if (t[0] == b || t[1] == b || t[2] == b) return true;
    }
    return false;
  }

  /// The vertex of face f that is neither a nor b.
  [[nodiscard]] VertexId opposite(std::uint32_t f, VertexId a, VertexId b) const {
    for (VertexId v : faces_[f])
      if (v != a && v != b) return v;
    return kNoVertex;
  }

  [[nodiscard]] std::size_t memory_bytes() const {
    std::size_t b = faces_.capacity() * sizeof(Face) + scan_of_.capacity() * sizeof(std::uint32_t) +
                    faces_of_.capacity() * sizeof(std::vector<std::uint32_t>) +
                    version_.capacity() * sizeof(std::uint32_t);
    for (const auto& v : faces_of_) b += v.capacity() * sizeof(std::uint32_t);
    return b;
  }

private:
  static void erase_from(std::vector<std::uint32_t>& v, std::uint32_t f) {
    for (std::size_t i = 0; i < v.size(); ++i)
      if (v[i] == f) {
        v[i] = v.back();
        v.pop_back();
        return;
      }
  }

  std::vector<Face> faces_;
  std::vector<std::uint32_t> scan_of_;
  std::vector<std::vector<std::uint32_t>> faces_of_;
  std::vector<std::uint32_t> version_;
};

}  // namespace nbs::detail
