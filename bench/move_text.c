/* move_text.so (bench/README.md, "Placement"): preloaded into a benchmark
 * (LD_PRELOAD=.../libdyngen_move_text.so), it moves the program's machine code into freshly
 * allocated memory before main runs. The virtual addresses stay the same, so every instruction,
 * constant and stack slot keeps its address; only the physical pages that hold the code change.
 * scripts/placement.sh uses it to tell a copy that is slow because of where its code landed in
 * physical memory from one that is slow for any other reason.
 *
 * The kernel hands out recently freed pages first, so programs run one after the other would
 * get much the same pages; holding a random number of other pages (up to 32 MiB) while the code
 * moves makes each run a draw of its own.
 *
 * Linux only: it reads /proc/self/maps and uses mremap. It writes one line to stderr saying what
 * it moved, or why it moved nothing. */
#define _GNU_SOURCE
#include <stdio.h>
#include <string.h>
#include <sys/mman.h>
#include <time.h>
#include <unistd.h>

/* The executable mappings of the file at exe: [from, to) pairs, at most max of them. */
static int executable_mappings(const char* exe, unsigned long* from, unsigned long* to, int max) {
  FILE* maps = fopen("/proc/self/maps", "r");
  if (!maps) return 0;
  char line[8192];
  int count = 0;
  while (count < max && fgets(line, sizeof line, maps)) {
    unsigned long a, b;
    char permissions[8], path[4096] = "";
    if (sscanf(line, "%lx-%lx %7s %*s %*s %*s %4095s", &a, &b, permissions, path) < 3) continue;
    if (permissions[2] != 'x' || strcmp(path, exe) != 0) continue;
    from[count] = a;
    to[count] = b;
    ++count;
  }
  fclose(maps);
  return count;
}

/* A copy of [from, to) in new anonymous pages, put in place of the original in one mremap: the
 * code that runs here is the library's, not the program's, so nothing executes a half-moved
 * mapping. */
static int move(unsigned long from, unsigned long to) {
  const size_t length = to - from;
  void* fresh = mmap(NULL, length, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (fresh == MAP_FAILED) return 0;
  memcpy(fresh, (const void*)from, length);
  if (mprotect(fresh, length, PROT_READ | PROT_EXEC) != 0 ||
      mremap(fresh, length, length, MREMAP_MAYMOVE | MREMAP_FIXED, (void*)from) == MAP_FAILED) {
    munmap(fresh, length);
    return 0;
  }
  return 1;
}

__attribute__((constructor)) static void move_text(void) {
  char exe[4096];
  const ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
  if (n <= 0) {
    fprintf(stderr, "move_text: cannot read /proc/self/exe; nothing moved\n");
    return;
  }
  exe[n] = '\0';
  unsigned long from[16], to[16];
  const int count = executable_mappings(exe, from, to, 16);
  struct timespec now;
  clock_gettime(CLOCK_REALTIME, &now);
  const size_t held = 4096 * (((unsigned long)now.tv_nsec ^ (unsigned long)getpid() * 2654435761u) % 8192);
  char* hold = held ? mmap(NULL, held, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0)
                    : MAP_FAILED;
  if (hold != MAP_FAILED)
    for (size_t page = 0; page < held; page += 4096) hold[page] = 1;
  unsigned long moved = 0;
  for (int i = 0; i < count; ++i)
    if (move(from[i], to[i])) moved += to[i] - from[i];
  if (hold != MAP_FAILED) munmap(hold, held);
  fprintf(stderr, "move_text: moved %lu KiB of code of %s to fresh pages (%zu KiB held aside)\n",
          moved / 1024, exe, held / 1024);
}
