// Runs a command (its standard output to /dev/null) and prints "<wall ms> <peak RSS KiB> <exit code>".
//
// The benchmarks time statepack with this rather than `date +%s%N` around `/usr/bin/time`: on this
// project's machine those add about 12 ms to every figure (two more programs started inside the timed
// span), a third of a warm repack. The clock starts just before the fork and stops once the child is
// reaped: the command's own start, run and exit, as a build system pays them. This program is small, so
// the peak RSS the kernel reports for the child (which counts its pages before exec) is the command's.
// Built by the benchmark scripts themselves (cc -O2), so that they need nothing else.
#include <fcntl.h>
#include <stdio.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

int main(int argc, char** argv) {
  if (argc < 2) {
    fprintf(stderr, "usage: timed_run <command> [arguments...]\n");
    return 2;
  }
  struct timespec start, end;
  clock_gettime(CLOCK_MONOTONIC, &start);
  const pid_t pid = fork();
  if (pid < 0) return perror("fork"), 2;
  if (pid == 0) {
    const int null = open("/dev/null", O_WRONLY);
    if (null >= 0) dup2(null, 1);
    execvp(argv[1], argv + 1);
    perror(argv[1]);
    _exit(127);
  }
  int status = 0;
  struct rusage usage;
  if (wait4(pid, &status, 0, &usage) != pid) return perror("wait4"), 2;
  clock_gettime(CLOCK_MONOTONIC, &end);
  const double ms = (end.tv_sec - start.tv_sec) * 1e3 + (end.tv_nsec - start.tv_nsec) / 1e6;
  printf("%.0f %ld %d\n", ms, usage.ru_maxrss, WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status));
  return 0;
}
