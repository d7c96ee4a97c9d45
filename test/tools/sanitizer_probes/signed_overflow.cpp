// A signed overflow in the project's own code: UBSan must report it under the
// sanitized build's flags (test/tools/test_sanitizer_flags.sh). Without a
// report the program exits 0.
#include <climits>
#include <cstdio>

int add(int a, int b) { return a + b; }

int main(int argc, char**) {
  std::printf("%d\n", add(INT_MAX, argc));
  return 0;
}
