// pi, for the tests' geometry (C++17 has no std::numbers). One definition
// for every test: the test sources are compiled several to a translation unit
// (CMakeLists.txt, SKELSEG_UNITY_TESTS), where copies of their own collide.
#pragma once

namespace skelseg::test {

constexpr double kPi = 3.14159265358979323846;

}  // namespace skelseg::test
