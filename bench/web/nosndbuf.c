// Evidence for bench/web/replay_bench.sh (NOSNDBUF=1), never shipped:
// setsockopt(SO_SNDBUF) becomes a no-op in the process it is preloaded into
// (groundsim-web only), so the kernel autotunes every socket's send buffer.
#define _GNU_SOURCE
#include <dlfcn.h>
#include <sys/socket.h>
int setsockopt(int fd, int level, int name, const void* v, socklen_t n) {
  static int (*real)(int, int, int, const void*, socklen_t);
  if (!real) real = dlsym(RTLD_NEXT, "setsockopt");
  if (level == SOL_SOCKET && name == SO_SNDBUF) return 0;
  return real(fd, level, name, v, n);
}
