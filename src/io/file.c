/*
 * Whole-file reading, atomic output files (with the registry of their
 * temporaries that a fatal signal removes) and format dispatch.
 */
#define _GNU_SOURCE /* O_TMPFILE; and POSIX: mkstemp, fsync, fchmod, fchown, fdopen, readlink, lstat, sigaction, linkat */

#include "vn_io.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <signal.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

vn_io_result vn_io_read_all(const char* path, char** data, size_t* size, vn_io_error* error)
{
	*data = NULL;
	*size = 0;
	FILE* in = fopen(path, "rb");
	if (!in)
		return vn_io_fail(error, vn_io_error_open, "%s: cannot open: %s", path, strerror(errno));

	/* A regular file is read with one allocation: its size, one byte more so
	 * that the first fread already sees the end, and the NUL. Pipes and files
	 * that lie about their size grow by doubling. */
	size_t capacity = 4096;
	struct stat st;
	if (fstat(fileno(in), &st) == 0 && S_ISREG(st.st_mode) && (uintmax_t)st.st_size < SIZE_MAX - 2 &&
	    (size_t)st.st_size + 2 > capacity)
		capacity = (size_t)st.st_size + 2;

	char* buffer = malloc(capacity);
	size_t length = 0;
	vn_io_result result = vn_io_success;
	while (buffer) {
		if (capacity - length < 2) {
			char* larger = capacity <= SIZE_MAX / 2 ? realloc(buffer, capacity * 2) : NULL;
			if (!larger) {
				free(buffer);
				buffer = NULL;
				break;
			}
			buffer = larger;
			capacity *= 2;
		}
		size_t wanted = capacity - 1 - length;
		size_t got = fread(buffer + length, 1, wanted, in);
		length += got;
		if (got < wanted)
			break;
	}
	if (!buffer)
		result = vn_io_fail(error, vn_io_error_memory, "%s: out of memory reading the file", path);
	else if (ferror(in))
		result = vn_io_fail(error, vn_io_error_open, "%s: cannot read: %s", path, strerror(errno));
	fclose(in);
	if (result != vn_io_success) {
		free(buffer);
		return result;
	}
	buffer[length] = '\0';
	*data = buffer;
	*size = length;
	return vn_io_success;
}

vn_io_result vn_io_read_with(const char* path, vn_io_memory_reader parse, vn_io_mesh* mesh, vn_io_error* error)
{
	char* data;
	size_t size;
	memset(mesh, 0, sizeof *mesh);
	vn_io_result result = vn_io_read_all(path, &data, &size, error);
	if (result != vn_io_success)
		return result;
	result = parse(data, size, path, mesh, error);
	free(data);
	return result;
}

static vn_io_result unknown_extension(const char* path, vn_io_error* error)
{
	char known[256];
	vn_io_format_list(vn_io_list_extensions, known, sizeof known);
	return vn_io_fail(error, vn_io_error_format, "%s: unknown file extension (vn knows %s)", path, known);
}

vn_io_result vn_io_read_file(const char* path, const vn_io_format* format, vn_io_mesh* mesh, vn_io_error* error)
{
	memset(mesh, 0, sizeof *mesh);
	if (!format)
		format = vn_io_format_for_path(path);
	if (!format)
		return unknown_extension(path, error);
	if (!format->read)
		return vn_io_fail(error, vn_io_error_unsupported, "%s: vn cannot read %s files", path, format->name);
	return format->read(path, mesh, error);
}

/* ------------------------------------------------------------------ temporary-file registry */

/* The temporaries of every open vn_io_output, for the signal handler below:
 * process-wide state (see vn_io_remove_temporaries_on_signal). Slots are
 * claimed and cleared atomically, and lock-free atomics may be read in a
 * signal handler. The strings belong to their vn_io_output. */
#define REGISTRY_SIZE 1024
_Static_assert(ATOMIC_POINTER_LOCK_FREE == 2, "the signal handler reads the registry without locks");
static _Atomic(const char*) registry[REGISTRY_SIZE];

static int register_temporary(const char* temporary)
{
	for (int i = 0; i < REGISTRY_SIZE; i++) {
		const char* empty = NULL;
		if (atomic_compare_exchange_strong(&registry[i], &empty, temporary))
			return i;
	}
	return -1;
}

static const int fatal_signals[] = {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT, SIGINT, SIGTERM, SIGHUP};
#define FATAL_COUNT (sizeof fatal_signals / sizeof fatal_signals[0])
#define FAULT_COUNT 4 /* the first four: raised by the kernel at a faulting instruction */
static struct sigaction previous_actions[FATAL_COUNT];

/* Async-signal-safe: atomic loads, unlink, sigaction and raise only. */
static void remove_temporaries(int signal_number, siginfo_t* info, void* context)
{
	(void)context;
	for (int i = 0; i < REGISTRY_SIZE; i++) {
		const char* temporary = atomic_load(&registry[i]);
		if (temporary)
			unlink(temporary);
	}
	size_t k = 0;
	while (fatal_signals[k] != signal_number)
		k++;
	sigaction(signal_number, &previous_actions[k], NULL);
	/* A fault the kernel raised (si_code > 0) recurs when the instruction runs
	 * again, now under the previous action, which then sees where it happened
	 * (a sanitizer reports it); a signal sent by kill or raise is sent again. */
	if (k < FAULT_COUNT && info->si_code > 0)
		return;
	raise(signal_number);
}

void vn_io_remove_temporaries_on_signal(void)
{
	struct sigaction action;
	memset(&action, 0, sizeof action);
	action.sa_sigaction = remove_temporaries;
	action.sa_flags = SA_SIGINFO;
	sigemptyset(&action.sa_mask);
	for (size_t k = 0; k < FATAL_COUNT; k++)
		sigaddset(&action.sa_mask, fatal_signals[k]);
	for (size_t k = 0; k < FATAL_COUNT; k++) {
		struct sigaction current;
		if (sigaction(fatal_signals[k], NULL, &current) != 0)
			continue;
		const int ignored = !(current.sa_flags & SA_SIGINFO) && current.sa_handler == SIG_IGN;
		const int ours = (current.sa_flags & SA_SIGINFO) && current.sa_sigaction == remove_temporaries;
		if (ignored || ours)
			continue;
		previous_actions[k] = current;
		sigaction(fatal_signals[k], &action, NULL);
	}
}

/* ------------------------------------------------------------------ output files */

/* The folder part of path, with its slash ("a/b/" for "a/b/c"; "" for "c"). */
static size_t folder_length(const char* path)
{
	const char* slash = strrchr(path, '/');
	return slash ? (size_t)(slash - path) + 1 : 0;
}

static char* copy_text(const char* text, size_t length)
{
	char* copy = malloc(length + 1);
	if (copy) {
		memcpy(copy, text, length);
		copy[length] = '\0';
	}
	return copy;
}

static const char* file_kind(mode_t mode)
{
	return S_ISDIR(mode) ? "folder" : S_ISCHR(mode) ? "character device" : S_ISBLK(mode) ? "block device"
	       : S_ISFIFO(mode) ? "FIFO (pipe)" : S_ISSOCK(mode) ? "socket" : "special file";
}

/* Follows the links from path to the file they end at (absent when the last
 * link dangles): *target, malloc'd. */
static vn_io_result follow_links(const char* path, char** target, vn_io_error* error)
{
	char* current = copy_text(path, strlen(path));
	for (int links = 0; current; links++) {
		struct stat st;
		char link[PATH_MAX];
		ssize_t n;
		if (lstat(current, &st) != 0 || !S_ISLNK(st.st_mode)) {
			*target = current;
			return vn_io_success;
		}
		/* 40: Linux's own limit on the links one lookup follows. */
		if (links == 40 || (n = readlink(current, link, sizeof link)) < 0 || (size_t)n == sizeof link) {
			const int why = links == 40 ? ELOOP : n < 0 ? errno : ENAMETOOLONG;
			free(current);
			return vn_io_fail(error, vn_io_error_write, "%s: cannot follow its symbolic links: %s", path,
			                  strerror(why));
		}
		/* A relative link is relative to the folder that holds it. */
		const size_t folder = link[0] == '/' ? 0 : folder_length(current);
		char* next = malloc(folder + (size_t)n + 1);
		if (next) {
			memcpy(next, current, folder);
			memcpy(next + folder, link, (size_t)n);
			next[folder + (size_t)n] = '\0';
		}
		free(current);
		current = next;
	}
	return vn_io_fail(error, vn_io_error_memory, "%s: out of memory", path);
}

vn_io_result vn_io_output_check(const char* path, char** target, vn_io_error* error)
{
	if (target)
		*target = NULL;
	struct stat st;
	/* stat follows every link, also the kernel's own like /dev/stdout -> /proc/self/fd/1 -> a pipe. */
	if (stat(path, &st) == 0 && !S_ISREG(st.st_mode))
		return vn_io_fail(error, vn_io_error_write,
		                  "%s is a %s, not a regular file: give the path of a file to create or replace", path,
		                  file_kind(st.st_mode));
	char* resolved;
	vn_io_result result = follow_links(path, &resolved, error);
	if (result != vn_io_success)
		return result;
	const size_t length = folder_length(resolved);
	/* "" is the working folder; "/" keeps its slash, "a/" loses it for the message. */
	char* folder = length == 0 ? copy_text(".", 1) : copy_text(resolved, length > 1 ? length - 1 : length);
	if (!folder)
		result = vn_io_fail(error, vn_io_error_memory, "%s: out of memory", path);
	else if (stat(folder, &st) != 0)
		result = errno == ENOENT || errno == ENOTDIR
		             ? vn_io_fail(error, vn_io_error_write, "%s: the folder '%s' does not exist: create it first",
		                          path, folder)
		             : vn_io_fail(error, vn_io_error_write, "%s: cannot use the folder '%s': %s", path, folder,
		                          strerror(errno));
	else if (!S_ISDIR(st.st_mode))
		result = vn_io_fail(error, vn_io_error_write, "%s: '%s' is not a folder", path, folder);
	free(folder);
	if (result == vn_io_success && target)
		*target = resolved;
	else
		free(resolved);
	return result;
}

/* The mode bits a newly created file gets: umask() can only be read by
 * setting it, so it is set back at once. Another thread creating a file in
 * between would not see the mask; vn_io does not claim to be thread-safe
 * around writes. */
static mode_t current_umask(void)
{
	mode_t mask = umask(0);
	umask(mask);
	return mask;
}

/* mkstemp makes the file 0600: it gets the mode (and, where permitted, owner
 * and group) of the file it replaces, else that of any new file. */
static int take_attributes(int fd, const char* target)
{
	struct stat old;
	if (stat(target, &old) != 0)
		return errno == ENOENT ? fchmod(fd, 0666 & ~current_umask()) : -1;
	/* Only root may give a file away, and a group only to its members; the
	 * owner first, as chown clears set-user-ID bits. */
	if (fchown(fd, old.st_uid, old.st_gid) != 0 && fchown(fd, (uid_t)-1, old.st_gid) != 0 && errno != EPERM)
		return -1;
	return fchmod(fd, old.st_mode & 07777);
}

/* A file without a name in target's folder (its first `folder` bytes), or
 * -1 where O_TMPFILE (Linux, file systems that have it) or /proc/self/fd,
 * through which it is linked later, is missing. */
static int open_anonymous(const char* target, size_t folder)
{
#ifdef O_TMPFILE
	if (access("/proc/self/fd", X_OK) != 0)
		return -1;
	char* dir = folder ? copy_text(target, folder) : copy_text(".", 1);
	if (!dir)
		return -1;
	const int fd = open(dir, O_TMPFILE | O_WRONLY | O_CLOEXEC, 0600);
	free(dir);
	return fd;
#else
	(void)target, (void)folder;
	return -1;
#endif
}

/* Gives the anonymous temporary the name `name`; fails with EEXIST when
 * the name exists. */
static int link_anonymous(const vn_io_output* output, const char* name)
{
	char self[64];
	snprintf(self, sizeof self, "/proc/self/fd/%d", output->fd);
	return linkat(AT_FDCWD, self, AT_FDCWD, name, AT_SYMLINK_FOLLOW);
}

/* Links the anonymous temporary under its template ".NAME.XXXXXX" with the
 * X's made unique, as mkstemp would have named it. */
static int name_anonymous(vn_io_output* output)
{
	static const char letters[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789";
	char* x = output->temporary + strlen(output->temporary) - 6;
	struct timespec now;
	clock_gettime(CLOCK_REALTIME, &now);
	uint64_t state = (uint64_t)now.tv_nsec ^ ((uint64_t)getpid() << 32) ^ (uint64_t)(uintptr_t)output;
	for (int attempt = 0; attempt < 100; attempt++) {
		for (int i = 0; i < 6; i++) {
			state ^= state << 13, state ^= state >> 7, state ^= state << 17; /* xorshift64 */
			x[i] = letters[state % (sizeof letters - 1)];
		}
		if (link_anonymous(output, output->temporary) == 0)
			return 0;
		if (errno != EEXIST)
			return -1;
	}
	return -1;
}

static void release(vn_io_output* output)
{
	if (output->slot >= 0)
		atomic_store(&registry[output->slot], NULL);
	free(output->path);
	free(output->target);
	free(output->temporary);
	memset(output, 0, sizeof *output);
	output->fd = -1;
	output->slot = -1;
}

vn_io_result vn_io_output_open(vn_io_output* output, const char* path, vn_io_error* error)
{
	memset(output, 0, sizeof *output);
	output->fd = -1;
	output->slot = -1;
	vn_io_result result = vn_io_output_check(path, &output->target, error);
	if (result != vn_io_success)
		return result;
	/* "dir/name.off" -> "dir/.name.off.XXXXXX": the same folder, so that
	 * rename() stays within one file system and is atomic; hidden, so that a
	 * file left by a killed process does not look like output. */
	const size_t folder = folder_length(output->target), length = strlen(output->target);
	output->path = copy_text(path, strlen(path));
	output->temporary = malloc(length + 1 + sizeof ".XXXXXX");
	if (!output->path || !output->temporary) {
		release(output);
		return vn_io_fail(error, vn_io_error_memory, "%s: out of memory", path);
	}
	memcpy(output->temporary, output->target, folder);
	output->temporary[folder] = '.';
	memcpy(output->temporary + folder + 1, output->target + folder, length - folder);
	memcpy(output->temporary + length + 1, ".XXXXXX", sizeof ".XXXXXX");
	/* Registered before it exists: a signal between mkstemp and registering
	 * would leave it; unlinking the template's name meanwhile is harmless. */
	output->slot = register_temporary(output->temporary);
	if (output->slot < 0) {
		release(output);
		return vn_io_fail(error, vn_io_error_write, "%s: more than %d output files are open at once", path,
		                  REGISTRY_SIZE);
	}
	output->fd = open_anonymous(output->target, folder);
	output->anonymous = output->fd >= 0;
	if (!output->anonymous)
		output->fd = mkstemp(output->temporary);
	if (output->fd < 0) {
		result = vn_io_fail(error, vn_io_error_write, "%s: cannot create a temporary file next to %s: %s", path,
		                    output->target, strerror(errno));
		release(output);
		return result;
	}
	if (take_attributes(output->fd, output->target) != 0) {
		result = vn_io_fail(error, vn_io_error_write, "%s: cannot give the new file the mode and owner of the old one: %s", path,
		                    strerror(errno));
		vn_io_output_discard(output);
	}
	return result;
}

vn_io_result vn_io_output_close(vn_io_output* output, vn_io_error* error)
{
	if (output->fd < 0)
		return vn_io_success;
	/* A full disk often shows up only here. */
	int failed = fsync(output->fd) != 0;
	int why = errno;
	/* Closing an anonymous file would delete it: it gets its name first. */
	if (!failed && output->anonymous) {
		failed = name_anonymous(output) != 0;
		why = errno;
		output->anonymous = failed;
	}
	if (close(output->fd) != 0 && !failed) {
		failed = 1;
		why = errno;
	}
	output->fd = -1;
	return failed ? vn_io_fail(error, vn_io_error_write, "%s: cannot write: %s", output->path, strerror(why))
	              : vn_io_success;
}

vn_io_result vn_io_output_commit(vn_io_output* output, vn_io_error* error)
{
	/* An anonymous temporary takes the target's name itself when that is
	 * new: it is never visible under another. */
	if (output->anonymous && output->fd >= 0 && fsync(output->fd) == 0 && link_anonymous(output, output->target) == 0) {
		close(output->fd);
		output->fd = -1;
		release(output);
		return vn_io_success;
	}
	vn_io_result result = vn_io_output_close(output, error);
	if (result == vn_io_success && rename(output->temporary, output->target) != 0)
		result = vn_io_fail(error, vn_io_error_write, "%s: cannot replace the file: %s", output->path,
		                    strerror(errno));
	if (result != vn_io_success) {
		vn_io_output_discard(output);
		return result;
	}
	release(output);
	return vn_io_success;
}

void vn_io_output_discard(vn_io_output* output)
{
	if (output->fd >= 0)
		close(output->fd);
	if (output->temporary && !output->anonymous)
		unlink(output->temporary);
	release(output);
}

vn_io_result vn_io_write_file(const char* path, const vn_io_format* format, const vn_io_mesh* mesh,
                              const void* settings, vn_io_error* error)
{
	if (!format)
		format = vn_io_format_for_path(path);
	if (!format)
		return unknown_extension(path, error);
	if (!format->write)
		return vn_io_fail(error, vn_io_error_unsupported, "%s: vn cannot write %s files", path, format->name);

	vn_io_output output;
	vn_io_result result = vn_io_output_open(&output, path, error);
	if (result != vn_io_success)
		return result;
	/* The stream has a copy of the descriptor: output.fd stays open, as an
	 * anonymous temporary needs until commit. */
	const int copy = dup(output.fd);
	FILE* out = copy >= 0 ? fdopen(copy, "wb") : NULL;
	if (!out) {
		result = vn_io_fail(error, vn_io_error_write, "%s: cannot write: %s", path, strerror(errno));
		if (copy >= 0)
			close(copy);
		vn_io_output_discard(&output);
		return result;
	}
	result = format->write(out, path, mesh, settings, error);
	/* Buffered data reach the disk only here; a full disk often shows up in
	 * fflush or fsync rather than in the writer's fprintf calls. */
	if (result == vn_io_success && (fflush(out) != 0 || ferror(out) || fsync(fileno(out)) != 0))
		result = vn_io_fail(error, vn_io_error_write, "%s: cannot write: %s", path, strerror(errno));
	if (fclose(out) != 0 && result == vn_io_success)
		result = vn_io_fail(error, vn_io_error_write, "%s: cannot write: %s", path, strerror(errno));
	if (result != vn_io_success) {
		vn_io_output_discard(&output);
		return result;
	}
	return vn_io_output_commit(&output, error);
}

int vn_io_same_file(const char* a, const char* b)
{
	struct stat sa, sb;
	return stat(a, &sa) == 0 && stat(b, &sb) == 0 && sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
}
