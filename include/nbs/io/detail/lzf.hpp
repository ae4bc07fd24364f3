// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// LZF decompression (the format of liblzf, used by PCD's `DATA binary_compressed`), bounds-checked.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace nbs::io_detail {

/// Decompresses the LZF stream `in` into exactly `out_size` bytes. The stream is a sequence of runs: a control byte
/// c < 32 is followed by c + 1 literal bytes; otherwise len = c >> 5 (7: plus the next byte) and the offset
/// ((c & 31) << 8 | next byte) + 1 back copy len + 2 bytes already produced. Returns the reason as a message when
/// the stream is malformed (a run past either end, a reference before the start) or does not fill `out_size`.
[[nodiscard]] inline std::optional<std::string> lzf_decompress(std::string_view in, std::size_t out_size,
                                                               std::string& out) {
  out.assign(out_size, '\0');
  std::size_t ip = 0, op = 0;
  while (ip < in.size()) {
    std::size_t ctrl = static_cast<std::uint8_t>(in[ip++]);
    if (ctrl < 32) {
      const std::size_t n = ctrl + 1;
      if (n > in.size() - ip) return "literal run past the end of the compressed data";
      if (n > out_size - op) return "literal run past the declared uncompressed size";
      out.replace(op, n, in.substr(ip, n));
      ip += n;
      op += n;
      continue;
    }
    std::size_t len = ctrl >> 5;
    if (ip >= in.size()) return "back reference past the end of the compressed data";
    if (len == 7) {
      len += static_cast<std::uint8_t>(in[ip++]);
      if (ip >= in.size()) return "back reference past the end of the compressed data";
    }
    const std::size_t offset = (((ctrl & 31u) << 8) | static_cast<std::uint8_t>(in[ip++])) + 1;
    len += 2;
    if (offset > op) return "back reference before the start of the data";
    if (len > out_size - op) return "back reference past the declared uncompressed size";
    for (std::size_t k = 0; k < len; ++k, ++op) out[op] = out[op - offset];  // may overlap: byte by byte
  }
  if (op != out_size) return "decompresses to fewer bytes than declared";
  return std::nullopt;
}

}  // namespace nbs::io_detail
