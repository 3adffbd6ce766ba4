// What the Cortex-M harnesses share: a call's stack measured by painting, and numbers printed
// without a C library.
#pragma once

extern "C" void sh_write(const char* text);

namespace firmware {

constexpr unsigned paint = 0xC0FFEE11u;
constexpr int painted_words = 16384;  // 64 KiB below the call site

/// Runs call with the stack below the caller's stack pointer painted; raises worst to the bytes
/// it overwrote. A macro, so that the stack pointer read is the call site's.
#define FIRMWARE_MEASURED(call, worst)                                                    \
  do {                                                                                    \
    unsigned* top;                                                                        \
    __asm__ volatile("mov %0, sp" : "=r"(top));                                           \
    volatile unsigned* const bottom = top - firmware::painted_words;                      \
    for (volatile unsigned* p = bottom; p < top; ++p) *p = firmware::paint;               \
    call;                                                                                 \
    volatile unsigned* p = bottom;                                                        \
    while (p < top && *p == firmware::paint) ++p;                                         \
    const unsigned used = static_cast<unsigned>(reinterpret_cast<volatile char*>(top) -   \
                                                reinterpret_cast<volatile char*>(p));     \
    if (used > (worst)) (worst) = used;                                                   \
  } while (0)

/// Prints "label value\n".
inline void print_count(const char* label, unsigned value) {
  char line[64];
  char* out = line;
  for (const char* c = label; *c != 0; ++c) *out++ = *c;
  char digits[12];
  int n = 0;
  do digits[n++] = static_cast<char>('0' + value % 10);
  while ((value /= 10) != 0);
  while (n > 0) *out++ = digits[--n];
  *out++ = '\n';
  *out = 0;
  sh_write(line);
}

}  // namespace firmware
