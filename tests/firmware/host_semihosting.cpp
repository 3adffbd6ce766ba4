// The host's stand-in for the Cortex-M build's semihosting output (startup.c).
#include <cstdio>

extern "C" void sh_write(const char* text) { std::fputs(text, stdout); }
