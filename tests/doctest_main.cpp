// doctest's implementation and main(), compiled once for every doctest
// executable (mbrt_add_test links it) instead of once in each.
#define DOCTEST_CONFIG_IMPLEMENT_WITH_MAIN
#include <doctest/doctest.h>
