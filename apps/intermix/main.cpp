// intermix: the command-line program (render, compare, bench, eval, info, phantom).
#include <cstdio>

int main() {
  std::fprintf(stderr, "intermix: being built\n");
  return 1;
}
