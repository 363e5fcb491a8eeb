//! @file main.cpp
//! @brief doctest entry point for iso_unit_tests.
#define DOCTEST_CONFIG_IMPLEMENT_WITH_MAIN
#include <doctest/doctest.h>
