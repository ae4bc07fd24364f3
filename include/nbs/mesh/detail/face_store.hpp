// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Triangles with vertex→face adjacency. The directed edges of Fig. 3.9 are read off the faces: a face (a, b, c) is
/// counter-clockwise around the normal, so it is the left triangle of a→b, b→c and c→a.
/// Invariant kept by every caller: a directed edge belongs to at most one face (hence an undirected edge to at most
/// two, with consistent orientation). Each face also keeps which of its directed edges have no twin (border edges,
/// Eq. 4.1), so that the border is enumerated without adjacency lookups; add and replace only note what changed
/// (the invariant may be broken in between, e.g. during an edge flip) and refresh_border() brings the masks up to
/// date once the faces are consistent again. Not thread-safe.

#include <array>
#include <cstddef>
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
  /// Bit k set: no face holds the reverse of face(f)'s directed edge k → k + 1 (mod 3). Valid after
  /// refresh_border() (StreamingMesh calls it at the end of every insert).
  [[nodiscard]] unsigned border_mask(std::uint32_t f) const { return border_[f]; }
  [[nodiscard]] const std::vector<std::uint32_t>& faces_of(VertexId v) const { return faces_of_[v]; }
  [[nodiscard]] bool has_faces(VertexId v) const { return !faces_of_[v].empty(); }
  /// Changes whenever a face of v is added, replaced or reordered in faces_of(v) (wraps after 2^32 changes).
  [[nodiscard]] std::uint32_t version(VertexId v) const { return version_[v]; }

  /// Adds face (a, b, c); the caller guarantees the directed edges are free.
  std::uint32_t add(VertexId a, VertexId b, VertexId c, std::uint32_t scan) {
    const auto f = static_cast<std::uint32_t>(faces_.size());
    faces_.push_back({a, b, c});
    scan_of_.push_back(scan);
    border_.push_back(0);
    noted_.push_back(0);
    note_changed(f);
    for (VertexId v : {a, b, c}) {
      faces_of_[v].push_back(f);
      ++version_[v];
    }
    return f;
  }

  /// Replaces face f by (a, b, c), updating adjacency; the caller guarantees the directed edges are free.
  void replace(std::uint32_t f, VertexId a, VertexId b, VertexId c, std::uint32_t scan) {
    for (int k = 0; k < 3; ++k) removed_.push_back({faces_[f][k], faces_[f][(k + 1) % 3]});
    note_changed(f);
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
      if ((t[0] == a && t[1] == b) || (t[1] == a && t[2] == b) || (t[2] == a && t[0] == b)) return f;
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

  /// Updates the border masks after add / replace calls; precondition: the invariant holds again.
  void refresh_border() {
    for (const auto& [x, y] : removed_) {  // the twin y→x of a removed edge is a border edge unless x→y came back
      const std::uint32_t g = face_with(y, x);
      if (g == kNoFace) continue;
      const unsigned bit = edge_bit(g, y, x);
      border_[g] = static_cast<std::uint8_t>(face_with(x, y) == kNoFace ? border_[g] | bit : border_[g] & ~bit);
    }
    for (std::uint32_t f : changed_) {
      unsigned m = 0;
      for (int k = 0; k < 3; ++k) {
        const VertexId x = faces_[f][k], y = faces_[f][(k + 1) % 3];
        if (const std::uint32_t g = face_with(y, x); g != kNoFace) {
          border_[g] = static_cast<std::uint8_t>(border_[g] & ~edge_bit(g, y, x));
        } else {
          m |= 1u << k;
        }
      }
      border_[f] = static_cast<std::uint8_t>(m);
      noted_[f] = 0;
    }
    removed_.clear();
    changed_.clear();
  }

  [[nodiscard]] std::size_t memory_bytes() const {
    std::size_t b = faces_.capacity() * sizeof(Face) + scan_of_.capacity() * sizeof(std::uint32_t) + border_.capacity() + noted_.capacity() +
                    changed_.capacity() * sizeof(std::uint32_t) + removed_.capacity() * sizeof(removed_[0]) +
                    faces_of_.capacity() * sizeof(std::vector<std::uint32_t>) +
                    version_.capacity() * sizeof(std::uint32_t);
    for (const auto& v : faces_of_) b += v.capacity() * sizeof(std::uint32_t);
    return b;
  }

private:
  void note_changed(std::uint32_t f) {
    if (noted_[f]) return;
    noted_[f] = 1;
    changed_.push_back(f);
  }
  // Bit of the directed edge x → y in face g, which holds it.
  [[nodiscard]] unsigned edge_bit(std::uint32_t g, VertexId x, VertexId y) const {
    const Face& t = faces_[g];
    for (int k = 0; k < 3; ++k)
      if (t[k] == x && t[(k + 1) % 3] == y) return 1u << k;
    return 0;
  }
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
  std::vector<std::uint8_t> border_;                        ///< per face: border_mask
  std::vector<std::uint32_t> changed_;                      ///< faces added or replaced since refresh_border, once each
  std::vector<std::uint8_t> noted_;                         ///< per face: 1 while in changed_
  std::vector<std::array<VertexId, 2>> removed_;            ///< directed edges replaced away since refresh_border
  std::vector<std::vector<std::uint32_t>> faces_of_;
  std::vector<std::uint32_t> version_;
};

}  // namespace nbs::detail
