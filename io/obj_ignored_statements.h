#pragma once
// The OBJ statements CGAL 5.5's reader accepts and ignores (CGAL/IO/OBJ.h); any other, such as
// `l` (a polyline), makes it refuse the whole file. One table for CGAL's path (its error
// messages, io/polygon_soup_loader.cpp) and for the fast reader (io/obj_ascii_reader.h), which
// must accept exactly what CGAL accepts.

#include <array>
#include <string_view>

namespace exao {

inline constexpr std::array<std::string_view, 45> kObjIgnoredStatements{
    "vt",     "vn",    "vp",       "bevel",    "lod",        "ctech",     "c_interp", "usemap",
    "usemtl", "stech", "d_interp", "mtllib",   "shadow_obj", "trace_obj", "o",        "g",
    "s",      "p",     "cstype",   "deg",      "step",       "bmat",      "con",      "curv",
    "curv2",  "surf",  "parm",     "trim",     "hole",       "scrv",      "sp",       "end",
    "surf_1", "q0_1",  "q1_1",     "curv2d_1", "surf_2",     "q0_2",      "q1_2",     "curv2d_2",
    "bsp",    "bzp",   "cdc",      "cdp",      "res"};

}  // namespace exao
