/* The C side of uniarc_foreign (src/common/uniarc_foreign.f90): what Fortran cannot do itself.
 *
 * Interrupts (SIGINT, SIGTERM, SIGHUP, SIGXCPU) as a request to stop, polled by the step loop (docs/contracts.md,
 * "Interrupts"). The handler only records the signal's number in a volatile sig_atomic_t, the one
 * kind of object a handler may write (C11 7.14.1.1, POSIX signal-safety); the program reads it
 * between steps through uniarc_interrupt_signal and ends the run itself, with the steps traced.
 *
 * SA_RESETHAND: a second signal of the same kind has its default action (the program ends at once,
 * leaving its work directory and lock, as a SIGKILL does). SA_RESTART: system calls the signal
 * interrupts (write, fflush) are restarted, so a signal never turns into an I/O error.
 * A signal ignored when the program starts (nohup, a background job of a non-interactive shell)
 * stays ignored. */
#define _POSIX_C_SOURCE 200809L
#include <signal.h>
#include <string.h>

static volatile sig_atomic_t received_signal = 0;

static void record_signal(int number) { received_signal = number; }

static int catch_one(int number, int once) {
    struct sigaction action, previous;
    if (sigaction(number, NULL, &previous) != 0) return -1;
    if (previous.sa_handler == SIG_IGN) return 0;
    memset(&action, 0, sizeof action);
    action.sa_handler = record_signal;
    sigemptyset(&action.sa_mask);
    action.sa_flags = SA_RESTART | (once ? SA_RESETHAND : 0);
    return sigaction(number, &action, NULL);
}

/* Install the handler for SIGINT and SIGTERM, and for SIGHUP (the terminal closed) and SIGXCPU (the
 * CPU time limit, `ulimit -t`, reached: the hard limit's SIGKILL follows later), which ask a run to
 * stop as well; 0 on success, -1 if the system refused. */
int uniarc_catch_interrupts(void) {
    int status = catch_one(SIGINT, 1);
    if (catch_one(SIGTERM, 1) != 0) status = -1;
    if (catch_one(SIGHUP, 1) != 0) status = -1;
    /* the kernel sends SIGXCPU again every CPU-second past the soft limit: the handler stays, so that
     * a wind-down longer than a second is not killed by the second one (the hard limit's SIGKILL
     * still ends a run that goes on) */
    if (catch_one(SIGXCPU, 0) != 0) status = -1;
    return status;
}

/* The number of the last SIGINT or SIGTERM received since uniarc_catch_interrupts, or 0. */
int uniarc_interrupt_signal(void) { return (int)received_signal; }

/* The numbers of SIGINT, SIGTERM, SIGHUP and SIGXCPU on this system (which = 0, 1, 2, 3: 2, 15, 1
 * and 24 on Linux); -1 for another `which`. */
int uniarc_signal_number(int which) {
    switch (which) {
    case 0: return SIGINT;
    case 1: return SIGTERM;
    case 2: return SIGHUP;
    case 3: return SIGXCPU;
    default: return -1;
    }
}

#include <sys/resource.h>

/* The soft limit on the address space (RLIMIT_AS, `ulimit -v`) in bytes, or -1 when there is none. */
long long uniarc_address_space_limit(void) {
    struct rlimit limit;
    if (getrlimit(RLIMIT_AS, &limit) != 0 || limit.rlim_cur == RLIM_INFINITY) return -1;
    return (long long)limit.rlim_cur;
}

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

/* Read the first at most `size` bytes of the regular file `path` into `buffer`, never blocking:
 * open(2) with O_NONBLOCK (a FIFO opened for reading would otherwise wait for a writer) and
 * O_NOFOLLOW (a symbolic link is not followed), then fstat(2) of what was opened. Returns the number
 * of bytes read, -1 when the file cannot be opened or read, -2 when it is not a regular file. */
int uniarc_read_regular_file(const char *path, char *buffer, int size) {
    struct stat status;
    ssize_t count;
    int descriptor = open(path, O_RDONLY | O_NONBLOCK | O_NOFOLLOW | O_CLOEXEC);
    if (descriptor < 0) return -1;
    if (fstat(descriptor, &status) != 0) {
        close(descriptor);
        return -1;
    }
    if (!S_ISREG(status.st_mode)) {
        close(descriptor);
        return -2;
    }
    count = read(descriptor, buffer, size > 0 ? (size_t)size : 0);
    close(descriptor);
    return count < 0 ? -1 : (int)count;
}

#include <errno.h>

/* Whether the process `pid` exists on this host: kill(pid, 0) sends nothing and fails with ESRCH
 * only when there is no such process (EPERM: it exists, owned by another user). 1 exists, 0 gone,
 * -1 unknown (pid ≤ 0, or another failure): a lock is taken over only on 0 (docs/contracts.md). */
int uniarc_process_exists(int pid) {
    if (pid <= 0) return -1;
    if (kill((pid_t)pid, 0) == 0) return 1;
    if (errno == ESRCH) return 0;
    if (errno == EPERM) return 1;
    return -1;
}

/* Whether the paths `first` and `second` name the same file (stat(2): the same device and inode,
 * links followed): 1 the same, 0 not, -1 when either cannot be looked at (no such file). */
int uniarc_same_file(const char *first, const char *second) {
    struct stat a, b;
    if (stat(first, &a) != 0 || stat(second, &b) != 0) return -1;
    return a.st_dev == b.st_dev && a.st_ino == b.st_ino ? 1 : 0;
}

/* This host's name (gethostname) into `buffer` of `size` bytes, NUL-terminated; its length, or -1. */
int uniarc_host_name(char *buffer, int size) {
    if (size <= 1 || gethostname(buffer, (size_t)size - 1) != 0) return -1;
    buffer[size - 1] = '\0';
    return (int)strlen(buffer);
}

#include <dirent.h>

/* The entries of a directory, one at a time: open (NULL when it cannot be read), the next entry's
 * name into `buffer` of `size` bytes (its length; -1 at the end; -2 for a name too long for it,
 * skipped), close. "." and ".." are skipped. */
void *uniarc_open_directory(const char *path) { return (void *)opendir(path); }

int uniarc_next_entry(void *directory, char *buffer, int size) {
    struct dirent *entry;
    size_t length;
    for (;;) {
        entry = readdir((DIR *)directory);
        if (entry == NULL) return -1;
        if (strcmp(entry->d_name, ".") == 0 || strcmp(entry->d_name, "..") == 0) continue;
        length = strlen(entry->d_name);
        if (size <= 0 || length >= (size_t)size) return -2;
        memcpy(buffer, entry->d_name, length + 1);
        return (int)length;
    }
}

void uniarc_close_directory(void *directory) { closedir((DIR *)directory); }
