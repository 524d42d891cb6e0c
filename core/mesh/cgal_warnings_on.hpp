// The end of a cgal_warnings_off.hpp block.  No include guard.
#pragma GCC diagnostic pop
