// contact2d: the program's first instructions. The program itself is libcontact2d_cli.so,
// whose libraries (gmsh with OpenCASCADE, FLTK and X11, Ipopt, SuiteSparse, Ceres: about a
// hundred) take the dynamic loader 0.05 to 1 s to map and relocate. Linked into the executable,
// that time came before main(), and a SIGINT in it killed the process by the signal: no exit
// 130, no line saying so (issue 32, finding 8). Here SIGINT and SIGTERM are held (blocked:
// one that arrives stays pending) before anything is loaded; contact2d_main installs the run
// verb's handler and restores the caller's mask, which delivers a held interrupt to it.
// Only the C library is used here, so this executable itself loads in about a millisecond.
#include <dlfcn.h>
#include <limits.h>
#include <malloc.h>
#include <signal.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace {

/// The folder of this executable ("" when /proc/self/exe cannot be read).
void own_folder(char* out, size_t size) {
  out[0] = '\0';
  char self[PATH_MAX];
  const ssize_t n = ::readlink("/proc/self/exe", self, sizeof self - 1);
  if (n <= 0) return;
  self[n] = '\0';
  char* slash = std::strrchr(self, '/');
  if (!slash) return;
  *slash = '\0';
  std::snprintf(out, size, "%s", self);
}

/// Keeps freed memory in the process for the next allocation. At every Newton iteration the
/// solver factorises anew and allocates and frees the same blocks of megabytes (the factor, the
/// dense surface block and its solves); glibc maps blocks above its threshold (128 kB, adapted
/// up to 32 MB) straight from the kernel and unmaps them on free, so each iteration faulted
/// every page in again: on a virtual machine that was a third of a frictional run's time
/// (Cattaneo-Mindlin: 175,000 page faults, 5.4 s; kept, 30,000 and 3.5 s). Blocks from 256 MB
/// up (a million-DOF factor) are still mapped and returned. A setting the user made through
/// GLIBC_TUNABLES or MALLOC_*_ wins. The program owns its process; the library (and Python's
/// module) leaves the host's allocator as it is.
void keep_freed_memory() {
  const char* tunables = std::getenv("GLIBC_TUNABLES");
  if ((tunables && std::strstr(tunables, "malloc")) || std::getenv("MALLOC_MMAP_THRESHOLD_") ||
      std::getenv("MALLOC_TRIM_THRESHOLD_"))
    return;
  mallopt(M_MMAP_THRESHOLD, 256 << 20);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
}

}  // namespace

int main(int argc, char** argv) {
  sigset_t held, caller;
  sigemptyset(&held);
  sigaddset(&held, SIGINT);
  sigaddset(&held, SIGTERM);
  sigprocmask(SIG_BLOCK, &held, &caller);
  keep_freed_memory();
  char folder[PATH_MAX];
  own_folder(folder, sizeof folder);
  // Beside the executable (the build tree), else where `cmake --install` puts it.
  const char* const kPlaces[] = {"", "/" C2D_CLI_LIBRARY_FROM_BINDIR};
  void* program = nullptr;
  char path[2 * PATH_MAX] = "";
  const char* error = "";
  for (const char* place : kPlaces) {
    std::snprintf(path, sizeof path, "%s%s/libcontact2d_cli.so", folder, place);
    program = ::dlopen(path, RTLD_LAZY | RTLD_LOCAL);
    if (program) break;
    const char* why = ::dlerror();
    if (why && ::access(path, F_OK) == 0) error = why;  // there but unloadable: say why
  }
  if (!program) {
    std::fprintf(stderr, "error: %s/libcontact2d_cli.so: expected the program's library beside "
                 "the executable or in " C2D_CLI_LIBRARY_FROM_BINDIR ", found %s\n",
                 folder, *error ? error : "none");
    return 1;
  }
  using Main = int (*)(int, char**, const sigset_t*);
  const auto run = reinterpret_cast<Main>(::dlsym(program, "contact2d_main"));
  if (!run) {
    std::fprintf(stderr, "error: %s: expected the function contact2d_main, found none\n", path);
    return 1;
  }
  return run(argc, argv, &caller);
}
