/*
 * Whole-file reading, atomic writing and format dispatch.
 */
#define _POSIX_C_SOURCE 200809L /* mkstemp, fsync, fchmod, fdopen, fileno */

#include "vn_io.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
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

static vn_io_result unknown_extension(const char* path, vn_io_error* error)
{
	char known[256] = "";
	for (size_t i = 0; vn_io_format_at(i); i++) {
		size_t used = strlen(known);
		snprintf(known + used, sizeof known - used, "%s%s", i ? " " : "", vn_io_format_at(i)->extensions);
	}
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

/* "dir/name.off" -> "dir/.name.off.XXXXXX": the same folder, so that rename()
 * stays within one file system and is atomic; hidden, so that a file left by
 * a killed process does not look like output. */
static char* temporary_template(const char* path)
{
	const char* slash = strrchr(path, '/');
	size_t folder = slash ? (size_t)(slash - path) + 1 : 0;
	size_t length = strlen(path);
	char* name = malloc(length + 1 + sizeof ".XXXXXX");
	if (!name)
		return NULL;
	memcpy(name, path, folder);
	name[folder] = '.';
	memcpy(name + folder + 1, path + folder, length - folder);
	memcpy(name + length + 1, ".XXXXXX", sizeof ".XXXXXX");
	return name;
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

vn_io_result vn_io_write_file(const char* path, const vn_io_format* format, const vn_io_mesh* mesh,
                              const void* settings, vn_io_error* error)
{
	if (!format)
		format = vn_io_format_for_path(path);
	if (!format)
		return unknown_extension(path, error);
	if (!format->write)
		return vn_io_fail(error, vn_io_error_unsupported, "%s: vn cannot write %s files", path, format->name);

	char* temporary = temporary_template(path);
	if (!temporary)
		return vn_io_fail(error, vn_io_error_memory, "%s: out of memory", path);
	int fd = mkstemp(temporary);
	if (fd < 0) {
		vn_io_result r = vn_io_fail(error, vn_io_error_write, "%s: cannot create a temporary file next to it: %s",
		                            path, strerror(errno));
		free(temporary);
		return r;
	}

	/* mkstemp makes the file 0600; the output should look like any new file. */
	vn_io_result result = vn_io_success;
	FILE* out = NULL;
	if (fchmod(fd, 0644 & ~current_umask()) != 0 || !(out = fdopen(fd, "wb"))) {
		result = vn_io_fail(error, vn_io_error_write, "%s: cannot write: %s", path, strerror(errno));
		close(fd);
	} else {
		result = format->write(out, path, mesh, settings, error);
		/* Buffered data reaches the disk only here; a full disk often shows
		 * up in fflush or fsync rather than in the writer's fprintf calls. */
		if (result == vn_io_success && (fflush(out) != 0 || ferror(out) || fsync(fileno(out)) != 0))
			result = vn_io_fail(error, vn_io_error_write, "%s: cannot write: %s", path, strerror(errno));
		if (fclose(out) != 0 && result == vn_io_success)
			result = vn_io_fail(error, vn_io_error_write, "%s: cannot write: %s", path, strerror(errno));
	}
	if (result == vn_io_success && rename(temporary, path) != 0)
		result = vn_io_fail(error, vn_io_error_write, "%s: cannot replace the file: %s", path, strerror(errno));
	if (result != vn_io_success)
		unlink(temporary);
	free(temporary);
	return result;
}

int vn_io_same_file(const char* a, const char* b)
{
	struct stat sa, sb;
	return stat(a, &sa) == 0 && stat(b, &sb) == 0 && sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
}
