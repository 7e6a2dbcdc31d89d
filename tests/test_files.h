/* Shared by the cmocka runners that make scratch folders (needs POSIX). */
#ifndef VN_TEST_FILES_H
#define VN_TEST_FILES_H

#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* Removes path and, for a folder, everything below it; links are removed,
 * not followed. Folders are made writable first (a test may have made one
 * read-only). */
static inline void remove_tree(const char* path)
{
	struct stat st;
	if (lstat(path, &st) != 0)
		return;
	if (!S_ISDIR(st.st_mode)) {
		unlink(path);
		return;
	}
	chmod(path, 0755);
	DIR* dir = opendir(path);
	struct dirent* entry;
	while (dir && (entry = readdir(dir))) {
		if (strcmp(entry->d_name, ".") == 0 || strcmp(entry->d_name, "..") == 0)
			continue;
		char child[1024];
		const int n = snprintf(child, sizeof child, "%s/%s", path, entry->d_name);
		if (n > 0 && (size_t)n < sizeof child)
			remove_tree(child);
	}
	if (dir)
		closedir(dir);
	rmdir(path);
}

/* The names in folder, sorted, joined by spaces, into out (truncated to
 * size); -1 when the folder cannot be read. */
static inline int list_names(const char* folder, char* out, size_t size)
{
	struct dirent** entries;
	int n = scandir(folder, &entries, NULL, alphasort);
	if (n < 0)
		return -1;
	out[0] = '\0';
	for (int i = 0; i < n; i++) {
		if (strcmp(entries[i]->d_name, ".") != 0 && strcmp(entries[i]->d_name, "..") != 0) {
			size_t used = strlen(out);
			snprintf(out + used, size - used, "%s%s", used ? " " : "", entries[i]->d_name);
		}
		free(entries[i]);
	}
	free(entries);
	return 0;
}

#endif /* VN_TEST_FILES_H */
