// Include before CGAL headers, and cgal_warnings_on.hpp after them: CGAL's
// headers trip radkit's warning flags (-Wshadow, -Wundef, ...), which are
// kept for radkit's own code.  No include guard: each use pushes once.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wundef"
#pragma GCC diagnostic ignored "-Wcast-align"
#pragma GCC diagnostic ignored "-Wnon-virtual-dtor"
#pragma GCC diagnostic ignored "-Wpointer-arith"
#pragma GCC diagnostic ignored "-Wformat-nonliteral"
#pragma GCC diagnostic ignored "-Wunused-parameter"
