/*
 * vn_io_output, the one way every output file is written: symbolic links
 * followed to their target, special files refused, the replaced file's mode
 * kept, and no temporary left behind by a failure or by a fatal signal
 * (checked in forked children that crash on purpose).
 */
#define _POSIX_C_SOURCE 200809L /* mkdtemp, symlink, mkfifo, mmap, fork, waitpid, chown */
#define _DEFAULT_SOURCE         /* mknod, makedev, MAP_ANONYMOUS (glibc) */

#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/wait.h>
#include <unistd.h>

#include "test_files.h"
#include "vn_io.h"

/* ------------------------------------------------------------------ helpers */

static char root[64]; /* the temporary folder, made by main */

/* root/sub, made fresh for one test. */
static void make_folder(char* out, size_t size, const char* sub)
{
	snprintf(out, size, "%s/%s", root, sub);
	assert_int_equal(mkdir(out, 0755), 0);
}

static void write_text(const char* path, const char* text)
{
	FILE* f = fopen(path, "wb");
	assert_non_null(f);
	assert_int_equal(fputs(text, f) >= 0, 1);
	assert_int_equal(fclose(f), 0);
}

static void assert_text(const char* path, const char* expected)
{
	char* data;
	size_t size;
	vn_io_error error;
	assert_int_equal(vn_io_read_all(path, &data, &size, &error), vn_io_success);
	assert_string_equal(data, expected);
	free(data);
}

static void assert_listing(const char* folder, const char* expected)
{
	char names[4096];
	assert_int_equal(list_names(folder, names, sizeof names), 0);
	assert_string_equal(names, expected);
}

/* Writes text to path through vn_io_output. */
static vn_io_result write_output(const char* path, const char* text, vn_io_error* error)
{
	vn_io_output output;
	vn_io_result r = vn_io_output_open(&output, path, error);
	if (r != vn_io_success)
		return r;
	assert_int_equal(write(output.fd, text, strlen(text)), (ssize_t)strlen(text));
	return vn_io_output_commit(&output, error);
}

static void assert_link(const char* path, const char* target)
{
	char text[256];
	ssize_t n = readlink(path, text, sizeof text - 1);
	assert_true(n > 0);
	text[n] = '\0';
	assert_string_equal(text, target);
}

/* ------------------------------------------------------------------ links */

static void test_writes_through_a_relative_link_chain(void** state)
{
	(void)state;
	char folder[256], path[512];
	make_folder(folder, sizeof folder, "chain");
	snprintf(path, sizeof path, "%s/a", folder);
	assert_int_equal(mkdir(path, 0755), 0);
	snprintf(path, sizeof path, "%s/b", folder);
	assert_int_equal(mkdir(path, 0755), 0);
	/* a/first -> ../b/second -> target.off, each relative to its own folder. */
	snprintf(path, sizeof path, "%s/a/first.off", folder);
	assert_int_equal(symlink("../b/second.off", path), 0);
	snprintf(path, sizeof path, "%s/b/second.off", folder);
	assert_int_equal(symlink("target.off", path), 0);
	snprintf(path, sizeof path, "%s/b/target.off", folder);
	write_text(path, "old\n");

	vn_io_error error;
	char* target;
	snprintf(path, sizeof path, "%s/a/first.off", folder);
	assert_int_equal(vn_io_output_check(path, &target, &error), vn_io_success);
	char expected[512];
	snprintf(expected, sizeof expected, "%s/a/../b/target.off", folder);
	assert_string_equal(target, expected);
	free(target);
	assert_int_equal(write_output(path, "new\n", &error), vn_io_success);
	assert_text(path, "new\n");
	assert_link(path, "../b/second.off");
	snprintf(path, sizeof path, "%s/b/second.off", folder);
	assert_link(path, "target.off");
	snprintf(path, sizeof path, "%s/a", folder);
	assert_listing(path, "first.off");
	snprintf(path, sizeof path, "%s/b", folder);
	assert_listing(path, "second.off target.off");
}

static void test_dangling_link_creates_its_target(void** state)
{
	(void)state;
	char folder[256], path[512], target[512];
	make_folder(folder, sizeof folder, "dangling");
	snprintf(path, sizeof path, "%s/sub", folder);
	assert_int_equal(mkdir(path, 0755), 0);
	snprintf(path, sizeof path, "%s/link.off", folder);
	assert_int_equal(symlink("sub/new.off", path), 0);
	vn_io_error error;
	assert_int_equal(write_output(path, "made\n", &error), vn_io_success);
	assert_link(path, "sub/new.off");
	snprintf(target, sizeof target, "%s/sub/new.off", folder);
	assert_text(target, "made\n");
	/* An absolute link. */
	snprintf(path, sizeof path, "%s/absolute.off", folder);
	snprintf(target, sizeof target, "%s/sub/absolute-target.off", folder);
	assert_int_equal(symlink(target, path), 0);
	assert_int_equal(write_output(path, "abs\n", &error), vn_io_success);
	assert_text(target, "abs\n");
	assert_listing(folder, "absolute.off link.off sub");
}

static void test_link_loop_and_missing_folder(void** state)
{
	(void)state;
	char folder[256], path[512], expected[1024];
	make_folder(folder, sizeof folder, "loop");
	snprintf(path, sizeof path, "%s/one.off", folder);
	assert_int_equal(symlink("two.off", path), 0);
	snprintf(path, sizeof path, "%s/two.off", folder);
	assert_int_equal(symlink("one.off", path), 0);
	vn_io_error error;
	assert_int_equal(write_output(path, "x", &error), vn_io_error_write);
	snprintf(expected, sizeof expected, "%s: cannot follow its symbolic links: Too many levels of symbolic links",
	         path);
	assert_string_equal(error.message, expected);

	/* A link into a folder that does not exist names that folder. */
	snprintf(path, sizeof path, "%s/nowhere.off", folder);
	assert_int_equal(symlink("gone/x.off", path), 0);
	assert_int_equal(write_output(path, "x", &error), vn_io_error_write);
	snprintf(expected, sizeof expected, "%s: the folder '%s/gone' does not exist: create it first", path, folder);
	assert_string_equal(error.message, expected);
	/* A file where a folder should be. */
	snprintf(path, sizeof path, "%s/file", folder);
	write_text(path, "x");
	snprintf(path, sizeof path, "%s/file/x.off", folder);
	assert_int_equal(vn_io_output_check(path, NULL, &error), vn_io_error_write);
	snprintf(expected, sizeof expected, "%s: '%s/file' is not a folder", path, folder);
	assert_string_equal(error.message, expected);
	assert_listing(folder, "file nowhere.off one.off two.off");
}

/* ------------------------------------------------------------------ special files */

static void expect_refused(const char* path, const char* kind)
{
	vn_io_error error;
	char expected[600];
	assert_int_equal(write_output(path, "x", &error), vn_io_error_write);
	snprintf(expected, sizeof expected, "%s is a %s, not a regular file: give the path of a file to create or replace",
	         path, kind);
	assert_string_equal(error.message, expected);
}

static void test_refuses_folders_fifos_devices(void** state)
{
	(void)state;
	char folder[256], path[512], link[512];
	struct stat st;
	make_folder(folder, sizeof folder, "special");
	snprintf(path, sizeof path, "%s/pipe.off", folder);
	assert_int_equal(mkfifo(path, 0644), 0);
	expect_refused(path, "FIFO (pipe)");
	assert_int_equal(lstat(path, &st), 0);
	assert_true(S_ISFIFO(st.st_mode));
	/* Through a link, which stays. */
	snprintf(link, sizeof link, "%s/to-pipe.off", folder);
	assert_int_equal(symlink("pipe.off", link), 0);
	expect_refused(link, "FIFO (pipe)");
	assert_link(link, "pipe.off");
	snprintf(path, sizeof path, "%s/dir.off", folder);
	assert_int_equal(mkdir(path, 0755), 0);
	expect_refused(path, "folder");
	/* Only checked, never opened: the system's own /dev/null stays safe
	 * whatever this test finds. */
	vn_io_error error;
	assert_int_equal(vn_io_output_check("/dev/null", NULL, &error), vn_io_error_write);
	assert_string_equal(error.message, "/dev/null is a character device, not a regular file: give the path of a file "
	                                   "to create or replace");
	if (geteuid() == 0) { /* a device node of our own, as root may make one */
		snprintf(path, sizeof path, "%s/null.off", folder);
		assert_int_equal(mknod(path, S_IFCHR | 0666, makedev(1, 3)), 0);
		expect_refused(path, "character device");
		assert_int_equal(lstat(path, &st), 0);
		assert_true(S_ISCHR(st.st_mode));
		unlink(path);
	}
	assert_listing(folder, "dir.off pipe.off to-pipe.off");
}

/* ------------------------------------------------------------------ mode and owner */

static void test_keeps_mode_and_owner(void** state)
{
	(void)state;
	char folder[256], path[512];
	struct stat st;
	make_folder(folder, sizeof folder, "mode");
	static const mode_t modes[] = {0640, 0444, 0755, 0600};
	vn_io_error error;
	for (size_t i = 0; i < sizeof modes / sizeof modes[0]; i++) {
		snprintf(path, sizeof path, "%s/m%o.off", folder, (unsigned)modes[i]);
		write_text(path, "old\n");
		assert_int_equal(chmod(path, modes[i]), 0);
		assert_int_equal(write_output(path, "new\n", &error), vn_io_success);
		assert_text(path, "new\n");
		assert_int_equal(stat(path, &st), 0);
		assert_int_equal(st.st_mode & 07777, modes[i]);
	}
	/* Through a link: the target's mode. */
	snprintf(path, sizeof path, "%s/link.off", folder);
	assert_int_equal(symlink("m444.off", path), 0);
	assert_int_equal(write_output(path, "again\n", &error), vn_io_success);
	assert_int_equal(stat(path, &st), 0);
	assert_int_equal(st.st_mode & 07777, 0444);
	/* Owner and group, which only root may give away. */
	if (geteuid() == 0) {
		snprintf(path, sizeof path, "%s/owned.off", folder);
		write_text(path, "old\n");
		assert_int_equal(chown(path, 1, 2), 0);
		assert_int_equal(write_output(path, "new\n", &error), vn_io_success);
		assert_int_equal(stat(path, &st), 0);
		assert_int_equal(st.st_uid, 1);
		assert_int_equal(st.st_gid, 2);
	}
	/* A new file: 0666 less the umask, like any created file. */
	mode_t saved = umask(027);
	snprintf(path, sizeof path, "%s/new.off", folder);
	assert_int_equal(write_output(path, "new\n", &error), vn_io_success);
	umask(saved);
	assert_int_equal(stat(path, &st), 0);
	assert_int_equal(st.st_mode & 07777, 0640);
}

/* ------------------------------------------------------------------ failures */

static void test_failed_commit_leaves_no_temporary(void** state)
{
	(void)state;
	char folder[256], path[512], inside[600];
	make_folder(folder, sizeof folder, "commit");
	snprintf(path, sizeof path, "%s/out.off", folder);
	vn_io_output output;
	vn_io_error error;
	assert_int_equal(vn_io_output_open(&output, path, &error), vn_io_success);
	/* A non-empty folder appears where the output goes: rename fails. */
	assert_int_equal(mkdir(path, 0755), 0);
	snprintf(inside, sizeof inside, "%s/keep", path);
	write_text(inside, "x");
	assert_int_equal(vn_io_output_commit(&output, &error), vn_io_error_write);
	assert_non_null(strstr(error.message, "out.off: cannot replace the file: "));
	assert_listing(folder, "out.off");
	vn_io_output_discard(&output); /* nothing more to do, and harmless */
}

static void test_registry_is_bounded(void** state)
{
	(void)state;
	char folder[256], path[512], expected[600];
	make_folder(folder, sizeof folder, "many");
	enum { count = 1024 };
	vn_io_output* outputs = calloc(count, sizeof *outputs);
	assert_non_null(outputs);
	vn_io_error error;
	for (int i = 0; i < count; i++) {
		snprintf(path, sizeof path, "%s/out%d.off", folder, i);
		assert_int_equal(vn_io_output_open(&outputs[i], path, &error), vn_io_success);
		assert_int_equal(vn_io_output_close(&outputs[i], &error), vn_io_success); /* keeps it registered */
	}
	snprintf(path, sizeof path, "%s/one-more.off", folder);
	vn_io_output extra;
	assert_int_equal(vn_io_output_open(&extra, path, &error), vn_io_error_write);
	snprintf(expected, sizeof expected, "%s: more than 1024 output files are open at once", path);
	assert_string_equal(error.message, expected);
	for (int i = 0; i < count; i++)
		vn_io_output_discard(&outputs[i]);
	free(outputs);
	assert_listing(folder, "");
	/* The slots are free again. */
	assert_int_equal(write_output(path, "x", &error), vn_io_success);
}

/* ------------------------------------------------------------------ fatal signals */

enum death { raise_segv, real_fault, raise_abort, raise_term, ignored_hup, killed };

/* In a forked child: installs the handlers, starts writing folder/out.off
 * (over an existing one), then dies the way `how` says. Exit codes 90+ are
 * the child's own failures. */
static void child(const char* folder, enum death how)
{
	char path[512];
	snprintf(path, sizeof path, "%s/out.off", folder);
	/* As in a fresh program: cmocka's own handlers (inherited) would catch the
	 * signal and go on running tests in this child. */
	static const int fatal[] = {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT, SIGINT, SIGTERM, SIGHUP};
	for (size_t i = 0; i < sizeof fatal / sizeof fatal[0]; i++)
		signal(fatal[i], SIG_DFL);
	if (how == ignored_hup)
		signal(SIGHUP, SIG_IGN);
	vn_io_remove_temporaries_on_signal();
	vn_io_remove_temporaries_on_signal(); /* a second call changes nothing */
	vn_io_output output;
	vn_io_error error;
	if (vn_io_output_open(&output, path, &error) != vn_io_success || write(output.fd, "partial", 7) != 7)
		_exit(90);
	switch (how) {
	case raise_segv: raise(SIGSEGV); break;
	case real_fault: {
		/* A fault the kernel raises, which no sanitizer reports as undefined behaviour. */
		volatile char* page = mmap(NULL, 4096, PROT_NONE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
		if (page == MAP_FAILED)
			_exit(91);
		(void)page[0];
		break;
	}
	case raise_abort: abort();
	case raise_term: raise(SIGTERM); break;
	case killed: raise(SIGKILL); break; /* no handler runs: the temporary must have no name */
	case ignored_hup:
		raise(SIGHUP); /* stays ignored: the output is finished */
		_exit(vn_io_output_commit(&output, &error) == vn_io_success ? 0 : 92);
	}
	_exit(93); /* still alive */
}

static void expect_death(const char* sub, enum death how, int signal_number)
{
	char folder[256], path[512];
	make_folder(folder, sizeof folder, sub);
	snprintf(path, sizeof path, "%s/out.off", folder);
	write_text(path, "original\n");
	fflush(NULL);
	pid_t pid = fork();
	assert_true(pid >= 0);
	if (pid == 0)
		child(folder, how);
	int status;
	assert_int_equal(waitpid(pid, &status, 0), pid);
	if (signal_number) {
		if (!WIFSIGNALED(status) || WTERMSIG(status) != signal_number)
			fail_msg("child status %#x, expected death by signal %d", status, signal_number);
	} else if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
		fail_msg("child status %#x, expected exit 0", status);
	}
	/* No ".out.off.XXXXXX" left, and the old output as it was (or, when the
	 * signal was ignored, the new one). */
	assert_listing(folder, "out.off");
	assert_text(path, signal_number ? "original\n" : "partial");
}

static void test_sigsegv_removes_temporaries(void** state)
{
	(void)state;
	expect_death("segv", raise_segv, SIGSEGV);
}

static void test_real_fault_removes_temporaries(void** state)
{
	(void)state;
	expect_death("fault", real_fault, SIGSEGV);
}

static void test_abort_removes_temporaries(void** state)
{
	(void)state;
	expect_death("abort", raise_abort, SIGABRT);
}

static void test_sigterm_removes_temporaries(void** state)
{
	(void)state;
	expect_death("term", raise_term, SIGTERM);
}

static void test_sigkill_leaves_no_temporary(void** state)
{
	(void)state;
	expect_death("kill", killed, SIGKILL);
}

static void test_ignored_signal_stays_ignored(void** state)
{
	(void)state;
	expect_death("hup", ignored_hup, 0);
}

/* ------------------------------------------------------------------ runner */

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(test_writes_through_a_relative_link_chain),
	    cmocka_unit_test(test_dangling_link_creates_its_target),
	    cmocka_unit_test(test_link_loop_and_missing_folder),
	    cmocka_unit_test(test_refuses_folders_fifos_devices),
	    cmocka_unit_test(test_keeps_mode_and_owner),
	    cmocka_unit_test(test_failed_commit_leaves_no_temporary),
	    cmocka_unit_test(test_registry_is_bounded),
	    cmocka_unit_test(test_sigsegv_removes_temporaries),
	    cmocka_unit_test(test_real_fault_removes_temporaries),
	    cmocka_unit_test(test_abort_removes_temporaries),
	    cmocka_unit_test(test_sigterm_removes_temporaries),
	    cmocka_unit_test(test_sigkill_leaves_no_temporary),
	    cmocka_unit_test(test_ignored_signal_stays_ignored),
	};
	snprintf(root, sizeof root, "/tmp/vn_test_output.XXXXXX");
	if (!mkdtemp(root)) {
		perror("mkdtemp");
		return 1;
	}
	int failures = cmocka_run_group_tests(tests, NULL, NULL);
	remove_tree(root);
	return failures;
}
