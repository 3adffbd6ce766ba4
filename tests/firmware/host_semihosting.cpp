// The host's stand-in for the Cortex-M build's semihosting output (examples/firmware/startup.c).
#include <cstdio>

extern "C" void sh_write(const char* text) { std::fputs(text, stdout); }
