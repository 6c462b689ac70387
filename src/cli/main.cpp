#include <cstdio>
int main() { std::puts("unjam: command line under construction"); return 0; }
