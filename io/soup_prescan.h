#pragma once
// Pre-scans of PLY and OFF files, before CGAL 5.5's readers see them. Those readers trust the
// counts a file states: they size arrays from them before reading a byte of data (a 200-byte
// PLY saying `element vertex 2147483648` with no properties spins while eating memory; an OFF
// face line starting `2000000000` asks for 16 GB), and some of their arrays are indexed by what
// a line holds without checking it (OFF colour entries).
//
// The rule: every count is checked against the bytes that remain in the file, with each
// stated item taking at least its smallest size (one byte per ASCII value, the type's size in
// binary), so nothing CGAL allocates can exceed a small multiple of the file's size. The scans
// follow CGAL's own reading (PLY: header, then every element's entries; OFF: one vertex or face
// a line, or big-endian binary) and read each byte once.

#include <string>

namespace exao {

/// "" when CGAL's PLY reader may be given the file at `path`, else the first problem, in words
/// (the header's shape, a count the file cannot hold, a list longer than the bytes left).
[[nodiscard]] std::string ply_problem(const std::string& path);

/// "" when CGAL's OFF reader may be given the file at `path`, else the first problem, in words
/// (a count the file cannot hold, a face line whose size disagrees with its numbers, colour
/// entries CGAL would read past).
[[nodiscard]] std::string off_problem(const std::string& path);

}  // namespace exao
