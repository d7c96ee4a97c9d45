// A heap overflow inside Eigen's assignment code: ASan must report it under
// the sanitized build's flags (test/tools/test_sanitizer_flags.sh). The
// buffer's address is printed after the stores, so they are not dead code;
// without a report the program exits 0.
#include <Eigen/Core>
#include <cstdio>
#include <vector>

int main(int argc, char**) {
  std::vector<double> three(3);
  Eigen::Map<Eigen::Vector4d> four(three.data());
  four.setConstant(argc);
  std::printf("%p %g\n", static_cast<void*>(three.data()), four.sum());
  return 0;
}
