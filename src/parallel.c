/* Running a computation on several workers with bit-identical results.
 *
 * Two phases: every worker first accumulates (and checks every index it
 * reads), then, if all indices were valid, normalizes into the output.
 *
 * Vertices are split into contiguous ranges, one per worker. Every worker
 * walks all faces in index order but adds only to the vertices it owns, then
 * normalizes them. Each vertex's sum is therefore formed by one worker, in
 * the same order and with the same operations whatever the worker count, and
 * workers never write the same memory: no locks, no reduction step. A face
 * whose corners fall in two ranges is evaluated by both workers; on meshes
 * with locality (indices roughly in face order) these are few. */
#include <pthread.h>
#include <stdlib.h>

#include "internal.h"
#include "simd.h"

/* Below this many vertices per worker, thread start-up costs more than it saves. */
#define VN_MIN_VERTICES_PER_THREAD 16384
#define VN_MAX_THREADS 256

typedef struct vn_task {
	const vn_work* work;
	vn_accumulate_fn accumulate;
	uint32_t lo, hi;
	vn_range_stats stats;
} vn_task;

/* Normalizes acc[v] into the output; returns 1 when it is the zero vector
 * (then stored only without keep_existing). */
VN_INLINE int finalize_one(const vn_work* w, uint32_t v)
{
	double a[3];
	memcpy(a, w->acc + 4 * (size_t)v, sizeof(a));
	const int zero = vn_normalize(a);
	if (!(zero && w->keep_existing))
		vn_store(w->out, v, a);
	return zero;
}

static void finalize(const vn_work* w, uint32_t lo, uint32_t hi, vn_range_stats* st)
{
	size_t zero = 0;
	for (uint32_t v = lo; v < hi; ++v)
		zero += finalize_one(w, v);
	st->zero_normals += zero;
}

#ifdef VN_HAVE_AVX2
/* finalize() four vertices at a time, with the same operations. */
static VN_AVX2 void finalize_avx2(const vn_work* w, uint32_t lo, uint32_t hi, vn_range_stats* st)
{
	const __m256d one = _mm256_set1_pd(1.0), lmin = _mm256_set1_pd(VN_LEN2_MIN), lmax = _mm256_set1_pd(VN_LEN2_MAX);
	size_t zero = 0;
	uint32_t v = lo;
	for (; v + 4 <= hi; v += 4) {
		const double* a = w->acc + 4 * (size_t)v;
		const __m256d a0 = _mm256_load_pd(a), a1 = _mm256_load_pd(a + 4);
		const __m256d a2 = _mm256_load_pd(a + 8), a3 = _mm256_load_pd(a + 12);
		const __m256d t0 = _mm256_unpacklo_pd(a0, a1), t1 = _mm256_unpackhi_pd(a0, a1);
		const __m256d t2 = _mm256_unpacklo_pd(a2, a3), t3 = _mm256_unpackhi_pd(a2, a3);
		const __m256d x = _mm256_permute2f128_pd(t0, t2, 0x20), y = _mm256_permute2f128_pd(t1, t3, 0x20);
		const __m256d z = _mm256_permute2f128_pd(t0, t2, 0x31);
		const __m256d len2 = vn_dot4(x, y, z, x, y, z);
		const __m256d in = _mm256_and_pd(_mm256_cmp_pd(len2, lmin, _CMP_GE_OQ), _mm256_cmp_pd(len2, lmax, _CMP_LE_OQ));
		if (_mm256_movemask_pd(in) != 15) {
			for (uint32_t k = 0; k < 4; ++k)
				zero += finalize_one(w, v + k);
			continue;
		}
		const __m256d inv = _mm256_div_pd(one, _mm256_sqrt_pd(len2));
		const __m256d nx = _mm256_mul_pd(x, inv), ny = _mm256_mul_pd(y, inv), nz = _mm256_mul_pd(z, inv);
		unsigned char* dst = (unsigned char*)w->out->data + (size_t)v * w->out->stride;
		if (w->out->type == vn_scalar_float32) {
			/* (float) rounds to nearest, as _mm256_cvtpd_ps does. */
			float f[12], fx[4], fy[4], fz[4];
			_mm_storeu_ps(fx, _mm256_cvtpd_ps(nx));
			_mm_storeu_ps(fy, _mm256_cvtpd_ps(ny));
			_mm_storeu_ps(fz, _mm256_cvtpd_ps(nz));
			for (int k = 0; k < 4; ++k)
				f[3 * k] = fx[k], f[3 * k + 1] = fy[k], f[3 * k + 2] = fz[k];
			if (w->out->stride == 3 * sizeof(float))
				memcpy(dst, f, sizeof(f));
			else
				for (int k = 0; k < 4; ++k)
					memcpy(dst + k * w->out->stride, f + 3 * k, 3 * sizeof(float));
		} else {
			double d[12], dx[4], dy[4], dz[4];
			_mm256_storeu_pd(dx, nx);
			_mm256_storeu_pd(dy, ny);
			_mm256_storeu_pd(dz, nz);
			for (int k = 0; k < 4; ++k)
				d[3 * k] = dx[k], d[3 * k + 1] = dy[k], d[3 * k + 2] = dz[k];
			for (int k = 0; k < 4; ++k)
				memcpy(dst + k * w->out->stride, d + 3 * k, 3 * sizeof(double));
		}
	}
	for (; v < hi; ++v)
		zero += finalize_one(w, v);
	st->zero_normals += zero;
}
#endif

/* Phase 1: zero the range's sums and add every face's contributions. */
static void* accumulate_task(void* arg)
{
	vn_task* t = (vn_task*)arg;
	const vn_work* w = t->work;
	memset(w->acc + 4 * (size_t)t->lo, 0, 4 * sizeof(double) * (size_t)(t->hi - t->lo));
	t->accumulate(w, t->lo, t->hi, &t->stats);
	return NULL;
}

/* Phase 2, once every index is known to be valid: write the range's normals. */
static void* finalize_task(void* arg)
{
	vn_task* t = (vn_task*)arg;
	const vn_work* w = t->work;
	if (w->seed)
		vn_smewcsa_finalize(w, t->lo, t->hi, &t->stats);
#ifdef VN_HAVE_AVX2
	else if (w->simd)
		finalize_avx2(w, t->lo, t->hi, &t->stats);
#endif
	else
		finalize(w, t->lo, t->hi, &t->stats);
	if (w->want_stats)
		t->stats.nonfinite_vertices += vn_count_nonfinite(w, t->lo, t->hi);
	return NULL;
}

/* Runs fn on every task: tasks 1..nt-1 on new threads, task 0 on the caller's;
 * a task whose thread cannot be started runs on the caller's too. */
static void run_all(void* (*fn)(void*), vn_task* tasks, unsigned nt, pthread_t* ids, unsigned char* started)
{
	for (unsigned t = 1; t < nt; ++t)
		started[t] = pthread_create(&ids[t], NULL, fn, &tasks[t]) == 0;
	fn(&tasks[0]);
	for (unsigned t = 1; t < nt; ++t) {
		if (started[t])
			pthread_join(ids[t], NULL);
		else
			fn(&tasks[t]);
	}
}

typedef struct vn_job {
	void (*fn)(void* ctx, unsigned t);
	void* ctx;
	unsigned t;
} vn_job;

static void* job_main(void* arg)
{
	const vn_job* j = (const vn_job*)arg;
	j->fn(j->ctx, j->t);
	return NULL;
}

void vn_parallel(unsigned nt, void (*fn)(void* ctx, unsigned t), void* ctx)
{
	vn_job jobs[VN_MAX_THREADS];
	pthread_t ids[VN_MAX_THREADS];
	unsigned char started[VN_MAX_THREADS];
	if (nt > VN_MAX_THREADS)
		nt = VN_MAX_THREADS;
	for (unsigned t = 0; t < nt; ++t)
		jobs[t].fn = fn, jobs[t].ctx = ctx, jobs[t].t = t;
	for (unsigned t = 1; t < nt; ++t)
		started[t] = pthread_create(&ids[t], NULL, job_main, &jobs[t]) == 0;
	if (nt)
		fn(ctx, 0);
	for (unsigned t = 1; t < nt; ++t) {
		if (started[t])
			pthread_join(ids[t], NULL);
		else
			fn(ctx, t);
	}
}

unsigned vn_worker_count(uint32_t nv, unsigned threads)
{
	unsigned nt = threads ? threads : 1;
	if (nt > VN_MAX_THREADS)
		nt = VN_MAX_THREADS;
	if ((size_t)nt * VN_MIN_VERTICES_PER_THREAD > nv)
		nt = nv / VN_MIN_VERTICES_PER_THREAD > 1 ? (unsigned)(nv / VN_MIN_VERTICES_PER_THREAD) : 1;
	return nt;
}

/* The work memory: 32-byte aligned accumulators, then the task records, the
 * thread ids and their started flags, plus slack for the alignment. */
size_t vn_work_bytes(uint32_t nv, unsigned threads)
{
	const size_t nt = vn_worker_count(nv, threads);
	return 4 * sizeof(double) * (size_t)nv + (sizeof(vn_task) + sizeof(pthread_t) + 1) * nt + 32;
}

vn_result vn_run(const vn_work* work, vn_accumulate_fn accumulate, const vn_options* o, vn_range_stats* st)
{
	const vn_allocator heap = vn_heap(&o->allocator);

	const uint32_t nv = work->vertex_count;
	const unsigned nt = vn_worker_count(nv, o->threads);
	const size_t need = vn_work_bytes(nv, o->threads);
	const int own = !(o->workspace && o->workspace_size >= need);
	unsigned char* block = own ? (unsigned char*)heap.allocate(heap.user, need) : (unsigned char*)o->workspace;
	if (!block)
		return vn_result_out_of_memory;
	const size_t acc_bytes = 4 * sizeof(double) * (size_t)nv, task_bytes = sizeof(vn_task) * nt;
	unsigned char* aligned = block + ((32 - ((uintptr_t)block & 31)) & 31);
	vn_work w = *work;
	w.acc = (double*)aligned;
	vn_task* tasks = (vn_task*)(aligned + acc_bytes);
	pthread_t* ids = (pthread_t*)(aligned + acc_bytes + task_bytes);

	for (unsigned t = 0; t < nt; ++t) {
		tasks[t].work = &w;
		tasks[t].accumulate = accumulate;
		tasks[t].lo = (uint32_t)((uint64_t)nv * t / nt);
		tasks[t].hi = (uint32_t)((uint64_t)nv * (t + 1) / nt);
		memset(&tasks[t].stats, 0, sizeof(tasks[t].stats));
	}

	/* Nothing reaches the caller's output until every worker has checked
	 * every index: the output is written in the second phase only. */
	unsigned char* started = (unsigned char*)(ids + nt);
	run_all(accumulate_task, tasks, nt, ids, started);
	int bad_index = 0;
	for (unsigned t = 0; t < nt; ++t)
		bad_index |= tasks[t].stats.bad_index;
	if (!bad_index) {
		run_all(finalize_task, tasks, nt, ids, started);
		for (unsigned t = 0; t < nt; ++t) {
			st->degenerate_faces += tasks[t].stats.degenerate_faces;
			st->zero_normals += tasks[t].stats.zero_normals;
			st->nonfinite_vertices += tasks[t].stats.nonfinite_vertices;
		}
	}
	if (own)
		heap.deallocate(heap.user, block);
	return bad_index ? vn_result_index_out_of_range : vn_result_success;
}
