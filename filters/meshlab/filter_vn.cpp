/*
 * "Re-Compute Vertex Normals (all published weightings)": MeshLab's vertex
 * normals from the vn library. The plugin only moves data: vn reads the
 * positions where CMeshO keeps them and (without weld or selection) writes
 * the normals straight into them; the faces become an index array. No
 * weighting scheme is implemented here (the face normals are vcglib's
 * formula).
 */
#include "filter_vn.h"

#include <vn.h>

#include <algorithm>
#include <cmath>
#include <system_error>
#include <thread>
#include <vector>

#include <vcg/complex/algorithms/update/normal.h>

namespace {

const char* const kMethod = "method";
const char* const kWeld = "weldByPosition";
const char* const kSelected = "onlySelected";
const char* const kFaceNormals = "faceNormals";

/* The filter's name, as MeshLab's menus and saved scripts (.mlx) know it. It
 * starts with the name of MeshLab's own filter, so that the Filters menu
 * (sorted by name) lists it on the next row. Scripts saved with the name of
 * vn 0.2 and before ("Recompute Vertex Normals (vn)") need the new name. */
const char* const kFilterName = "Re-Compute Vertex Normals (all published weightings)";

/* One entry per vn_method, in the enum's order (scripts store the index). */
struct MethodWords {
	const char* acronym; /* as the paper and the log name it */
	const char* label;   /* the dropdown entry */
	const char* help;    /* one line for the parameter's help: MeshLab 2020.09's Help
	                        mode sizes the label by its lines, so a line that
	                        wraps (over about 44 characters) pushes the last out */
};
const MethodWords kMethods[] = {
    {"MWE", "Equal weights (MWE, Gouraud 1971)", "every face counts the same"},
    {"MWA", "Angle weighted (MWA, default)", "by its corner angle (recommended)"},
    {"MWSELR", "Sine and edge-length reciprocals (MWSELR, Max 1999)", "angle sine over the two edge lengths"},
    {"MWAAT", "Area weighted (MWAAT, Max 1999)", "each face by its area"},
    {"MWELR", "Edge-length reciprocals (MWELR, Max 1999)", "one over the two edge lengths"},
    {"MWRELR", "Square roots of edge-length reciprocals (MWRELR, Max 1999)", "as MWELR, with square roots"},
    {"MEWCSA", "Cotangent weights, not for shading (MEWCSA, Desbrun 1999)", "cotangent weights, not for shading"},
    {"SMEWCSA", "Cotangent weights, sign corrected (SMEWCSA, Meyer 2003)", "cotangent weights, oriented outward"},
    {"QUADRIC", "Quadric fit on the 1-ring (QUADRIC)", "quadric fit over the 1-ring"},
    {"JET", "Cubic jet fit on the 2-ring (JET, Cazals 2003)", "cubic fit over the 2-ring"},
    {"ADAPTIVE", "Adaptive: fits where smooth, else MWA or MWAAT (ADAPTIVE)", "jet, wide fit, MWSELR, MWA, MWAAT"},
};
static_assert(sizeof kMethods / sizeof kMethods[0] == static_cast<size_t>(vn_method_count),
              "one entry per vn_method");

QString methodAcronym(int i)
{
	return QString::fromLatin1(kMethods[i].acronym);
}

QString methodHelp()
{
	QString t = QString::fromLatin1("How much each face around a vertex counts:");
	for (int i = 0; i < static_cast<int>(vn_method_count); ++i)
		t += QString::fromLatin1("<br><b>%1</b>: %2").arg(methodAcronym(i), QString::fromLatin1(kMethods[i].help));
	return t;
}

// Below this many vertices vn runs on the calling thread.
const uint32_t kThreadMinVertices = 200000;

QString errorPrefix()
{
	return QString::fromLatin1(kFilterName) + QString::fromLatin1(": ");
}

template <typename T>
bool usable3(const T* v)
{
	return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]) && (v[0] != 0 || v[1] != 0 || v[2] != 0);
}

} // namespace

FilterVnPlugin::FilterVnPlugin()
{
	typeList.push_back(FP_VN_VERTEX_NORMALS);
	for (VnActionID id : types())
		actionList.push_back(new QAction(filterName(id), this));
}

QString FilterVnPlugin::pluginName() const
{
	return QString::fromLatin1("FilterVn");
}

QString FilterVnPlugin::filterName(VnActionID filter) const
{
	switch (filter) {
	case FP_VN_VERTEX_NORMALS: return QString::fromLatin1(kFilterName);
	default: return QString();
	}
}

QString FilterVnPlugin::filterInfo(VnActionID filter) const
{
	switch (filter) {
	case FP_VN_VERTEX_NORMALS:
		// Short: MeshLab 2020.09's dialog shows it in a label that does not
		// scroll, and clips it when the Help mode makes the dialog taller.
		return QString::fromLatin1(
		           "Recomputes the per-vertex normals with any of the seven weightings of the faces around a "
		           "vertex that Jin, Lewis and West compared (<i>A comparison of algorithms for vertex normal "
		           "computation</i>, The Visual Computer 21, 2005), or with four schemes beyond the paper "
		           "(SMEWCSA and the local fits QUADRIC, JET, ADAPTIVE), in double precision (vn library %1). "
		           "A vertex that no face contributes to (a loose point, or one whose faces all have zero area) "
		           "keeps the normal it has, as with MeshLab's own filter; a layer without faces is refused.<br>"
		           "<b>MWA</b> (the default) is the one for shading: it depends least on how the surface is cut "
		           "into triangles. <b>ADAPTIVE</b> is the most accurate on smooth surfaces, at 15 to 70 times "
		           "MWA's time. <b>MWSELR</b> is exact on a sphere. <b>MEWCSA</b> is <b>not for shading</b>: "
		           "its sign is not corrected, so the normal points inwards where the surface curves the other "
		           "way (a third of the Stanford bunny's), which renders as black streaks.")
		    .arg(QString::fromLatin1(vn_version_string()));
	default: return QString();
	}
}

FilterVnPlugin::FilterClass FilterVnPlugin::getClass(VN_ACTION*) VN_CONST_2022
{
	return VnFilterBase::Normal;
}

VnFilterArity FilterVnPlugin::filterArity(VN_ACTION*) const
{
	return VnFilterBase::SINGLE_MESH;
}

int FilterVnPlugin::getPreConditions(VN_ACTION*) const
{
	return MeshModel::MM_FACENUMBER;
}

int FilterVnPlugin::postCondition(VN_ACTION*) const
{
	return MeshModel::MM_VERTNORMAL | MeshModel::MM_FACENORMAL;
}

void FilterVnPlugin::fillParameters(RichParameterList& par, bool somethingSelected) const
{
	QStringList methods;
	for (int i = 0; i < static_cast<int>(vn_method_count); ++i)
		methods << QString::fromLatin1(kMethods[i].label);
	par.addParam(RichEnum(QString::fromLatin1(kMethod), static_cast<int>(vn_method_mwa), methods,
	                      QString::fromLatin1("Weighting mode"), methodHelp()));
	par.addParam(RichBool(QString::fromLatin1(kWeld), false, QString::fromLatin1("Weld by position"),
	                      QString::fromLatin1("Vertices at one position (split by seams)<br>"
	                                          "get one normal, from all their faces.<br>"
	                                          "The mesh itself is not changed.")));
	par.addParam(RichBool(QString::fromLatin1(kSelected), somethingSelected,
	                      QString::fromLatin1("Affect only selected vertices"),
	                      QString::fromLatin1("Only the selected vertices and the vertices<br>"
	                                          "of the selected faces get new normals,<br>"
	                                          "computed from all their faces; the others<br>"
	                                          "keep theirs. On when something is selected.")));
	par.addParam(RichBool(QString::fromLatin1(kFaceNormals), true, QString::fromLatin1("Recompute face normals"),
	                      QString::fromLatin1("Also recompute the (unit) face normals.")));
}

/* The work arrays, kept between calls: allocating them afresh on every call
 * cost the bunny (36k vertices) more than vn's computation itself, in page
 * faults. Up to kKeepBytes stay allocated after a call (about a million
 * vertices); larger ones are freed. */
struct FilterVnPlugin::Work {
	std::vector<uint32_t> indices, remap;
	std::vector<Scalarm> normals;
	std::vector<char> chosen;
	std::vector<unsigned char> workspace;

	size_t bytes() const
	{
		return indices.capacity() * sizeof(uint32_t) + remap.capacity() * sizeof(uint32_t) +
		       normals.capacity() * sizeof(Scalarm) + chosen.capacity() + workspace.capacity();
	}
};

namespace {
const size_t kKeepBytes = size_t(64) << 20;
const size_t kWarmBytes = size_t(16) << 20;
const vn_scalar kScalar = sizeof(Scalarm) == sizeof(double) ? vn_scalar_float64 : vn_scalar_float32;
} // namespace

FilterVnPlugin::~FilterVnPlugin() = default;

QString FilterVnPlugin::run(MeshModel& mm, const RichParameterList& par, vcg::CallBackPos* cb)
{
	// One call at a time uses the kept arrays; another one at the same time
	// (MeshLab does not do that today) gets its own.
	std::unique_lock<std::mutex> lock(workMutex, std::try_to_lock);
	Work local;
	if (lock.owns_lock() && !work) work.reset(new Work);
	Work& w = lock.owns_lock() ? *work : local;
	QString err = compute(mm, par, cb, w);
	if (lock.owns_lock() && w.bytes() > kKeepBytes) w = Work();
	return err;
}

QString FilterVnPlugin::compute(MeshModel& mm, const RichParameterList& par, vcg::CallBackPos* cb, Work& w)
{
	CMeshO& m = mm.cm;
	const int methodIndex = par.getEnum(QString::fromLatin1(kMethod));
	if (methodIndex < 0 || methodIndex >= static_cast<int>(vn_method_count) ||
	    !vn_method_name(static_cast<vn_method>(methodIndex))) {
		QStringList l;
		for (int i = 0; i < static_cast<int>(vn_method_count); ++i) l << methodAcronym(i);
		return errorPrefix() + QString::fromLatin1("method %1 is not one of 0..%2 (%3)")
		                           .arg(methodIndex)
		                           .arg(static_cast<int>(vn_method_count) - 1)
		                           .arg(l.join(QString::fromLatin1(", ")));
	}
	const vn_method method = static_cast<vn_method>(methodIndex);
	const bool weld = par.getBool(QString::fromLatin1(kWeld));
	const bool onlySelected = par.getBool(QString::fromLatin1(kSelected));
	const bool faceNormals = par.getBool(QString::fromLatin1(kFaceNormals));

	// vn reads the positions where CMeshO keeps them, every slot of m.vert
	// (deleted ones too: no live face uses them, so they get nothing), and
	// the indices are positions in m.vert. Nothing is copied but the indices.
	const size_t vslots = m.vert.size();
	if (vslots > UINT32_MAX) return errorPrefix() + QString::fromLatin1("too many vertices");
	const bool anyDeleted = static_cast<size_t>(m.vn) != vslots;
	size_t live = vslots;
	if (anyDeleted) {
		live = 0;
		for (size_t i = 0; i < vslots; ++i)
			if (!m.vert[i].IsD()) ++live;
	}
	CVertexO* const base = vslots ? &m.vert[0] : nullptr;
	w.indices.resize(3 * static_cast<size_t>(m.fn));
	// With "only selected": the selected vertices and the vertices of the
	// selected faces (MeshLab's rectangle selection selects faces). MeshLab's
	// selection flags are left as they are.
	if (onlySelected) {
		w.chosen.assign(vslots, 0);
		for (size_t i = 0; i < vslots; ++i)
			if (!m.vert[i].IsD() && m.vert[i].IsS()) w.chosen[i] = 1;
	}
	size_t n = 0;
	for (auto fi = m.face.begin(); fi != m.face.end(); ++fi) {
		if (fi->IsD()) continue;
		if (n + 3 > w.indices.size()) w.indices.resize(n + 3); // m.fn out of date
		for (int k = 0; k < 3; ++k) {
			const CVertexO* v = fi->cV(k);
			const size_t i = static_cast<size_t>(v - base);
			if (i >= vslots || (anyDeleted && v->IsD()))
				return errorPrefix() + QString::fromLatin1("a face uses a deleted vertex");
			w.indices[n++] = static_cast<uint32_t>(i);
			if (onlySelected && fi->IsS()) w.chosen[i] = 1;
		}
	}
	if (n == 0)
		return QString::fromLatin1("%1 needs faces: this layer has %2 vertices and no faces; its normals "
		                           "are left as they are")
		    .arg(QString::fromLatin1(kFilterName))
		    .arg(live);
	// Progress only where it can be seen: a call on a small mesh takes about
	// a millisecond, and each report costs the GUI an event loop pass.
	if (!(vslots >= kThreadMinVertices)) cb = nullptr;
	if (cb) cb(10, "vn: mesh read");

	// P(), not cP(): vcglib's cP() returns a copy.
	const vn_positions pos = {&base->P()[0], vslots, sizeof(CVertexO), kScalar};
	vn_options options = {};
	// Threads pay off only on large meshes: starting them costs more than the
	// bunny's (35k vertices) whole computation.
	options.threads = vslots >= kThreadMinVertices ? std::thread::hardware_concurrency() : 1;
	if (weld) {
		w.remap.resize(vslots);
		vn_result r = vn_weld_positions(w.remap.data(), &pos, 0.0, &options);
		if (r != vn_result_success)
			return errorPrefix() + QString::fromLatin1("welding failed: %1").arg(QString::fromLatin1(vn_result_string(r)));
		for (size_t k = 0; k < n; ++k) w.indices[k] = w.remap[w.indices[k]];
	}
	// Without weld or selection vn writes straight into CVertexO::N() and
	// leaves alone every vertex it computes no normal for (keep_existing: no
	// face, or only zero-area ones), so such a vertex keeps its normal: the
	// filter never overwrites a normal it did not compute. With them, vn
	// writes into an array and the loop below picks what goes back.
	const bool direct = !weld && !onlySelected;
	if (!direct) w.normals.resize(3 * vslots);
	const vn_vectors out = direct ? vn_vectors{&base->N()[0], sizeof(CVertexO), kScalar}
	                              : vn_vectors{w.normals.data(), 0, kScalar};
	options.keep_existing = direct;
	w.workspace.resize(vn_workspace_size(vslots, &options));
	options.workspace = w.workspace.data();
	options.workspace_size = w.workspace.size();
	// vn gathers the positions in face order. Between two filter calls
	// MeshLab does enough other work to push the mesh out of the CPU caches,
	// and a gather from memory costs a miss per vertex; one walk over the
	// vertices in order, which the hardware prefetches, brings them back for
	// a fraction of that (bunny, 36k vertices: vn 1.6 ms -> 1.0 ms including
	// the walk). Up to kWarmBytes, which the caches can hold.
	if (vslots * sizeof(CVertexO) <= kWarmBytes) {
		Scalarm sum = 0;
		for (size_t i = 0; i < vslots; ++i) sum += base[i].P()[0];
		volatile Scalarm sink = sum; // the walk is for its loads only
		(void)sink;
	}
	vn_stats stats = {};
	vn_result r = vn_triangle_normals(&out, &pos, w.indices.data(), n, method, &options, &stats);
	if (r != vn_result_success)
		return errorPrefix() + QString::fromLatin1(vn_result_string(r));
	if (cb) cb(80, "vn: normals computed");

	size_t changed = 0, kept = 0, considered = 0;
	if (direct) {
		// vn's zero vectors: the live vertices kept, and every deleted slot
		// (no live face uses one).
		considered = live;
		kept = stats.zero_normals - (vslots - live);
		changed = live - kept;
	} else
		for (size_t i = 0; i < vslots; ++i) {
			CVertexO& v = m.vert[i];
			if ((anyDeleted && v.IsD()) || (onlySelected && !w.chosen[i])) continue;
			++considered;
			const Scalarm* nv = &w.normals[3 * static_cast<size_t>(weld ? w.remap[i] : i)];
			if (usable3(nv)) {
				v.N() = CVertexO::NormalType(nv[0], nv[1], nv[2]);
				++changed;
			} else
				++kept;
		}
	if (faceNormals) {
		// Unit face normals as vcg's PerFaceNormalized computes them; (0,0,0)
		// for a face of zero or non-finite area. On a large mesh the faces are
		// split between vn's threads: the pass waits on memory as much as vn.
		CFaceO* const faces = m.face.empty() ? nullptr : &m.face[0];
		auto faceRange = [faces](size_t lo, size_t hi) {
			for (size_t f = lo; f < hi; ++f) {
				CFaceO& face = faces[f];
				if (face.IsD()) continue;
				const Point3m p0 = face.cP(0);
				Point3m fn = (face.cP(1) - p0) ^ (face.cP(2) - p0);
				const Scalarm len = fn.Norm();
				face.N() = len > 0 && std::isfinite(len) ? fn / len : Point3m(0, 0, 0);
			}
		};
		const size_t nf = m.face.size(), parts = std::max<size_t>(1, options.threads);
		std::vector<std::thread> helpers;
		for (size_t t = 1; t < parts; ++t) {
			try {
				helpers.emplace_back(faceRange, nf * t / parts, nf * (t + 1) / parts);
			} catch (const std::system_error&) { // no thread: this one does the part
				faceRange(nf * t / parts, nf * (t + 1) / parts);
			}
		}
		faceRange(0, nf / parts);
		for (std::thread& h : helpers) h.join();
	}
	const QString msg =
	    QString::fromLatin1("%1, %2: %3 of %4 vertex normals changed%5, %6 kept (no face contributes); "
	                        "%7 of %8 faces degenerate%9")
	        .arg(QString::fromLatin1(kFilterName), methodAcronym(methodIndex))
	        .arg(changed)
	        .arg(live)
	        .arg(onlySelected ? QString::fromLatin1(" (only selected: %1 vertices)").arg(considered) : QString())
	        .arg(kept)
	        .arg(stats.degenerate_faces)
	        .arg(stats.faces)
	        .arg(weld ? QString::fromLatin1(", welded by position") : QString());
	VN_LOG("%s", qUtf8Printable(msg));
	if (cb) cb(100, "vn: done");
	return QString();
}

#if VN_MESHLAB_API >= 2022

RichParameterList FilterVnPlugin::initParameterList(const QAction* a, const MeshModel& m)
{
	RichParameterList par;
	if (ID(a) == FP_VN_VERTEX_NORMALS) fillParameters(par, m.cm.sfn > 0 || m.cm.svn > 0);
	return par;
}

std::map<std::string, QVariant> FilterVnPlugin::applyFilter(const QAction* a, const RichParameterList& par,
                                                            MeshDocument& md, unsigned int&, vcg::CallBackPos* cb)
{
	if (ID(a) != FP_VN_VERTEX_NORMALS) wrongActionCalled(a);
	QString err = run(*md.mm(), par, cb);
	if (!err.isEmpty()) throw MLException(err);
	return std::map<std::string, QVariant>();
}

#else

void FilterVnPlugin::initParameterSet(QAction* a, MeshModel& m, RichParameterList& par)
{
	if (ID(a) == FP_VN_VERTEX_NORMALS) fillParameters(par, m.cm.sfn > 0 || m.cm.svn > 0);
}

bool FilterVnPlugin::applyFilter(QAction* a, MeshDocument& md, const RichParameterList& par, vcg::CallBackPos* cb)
{
	if (ID(a) != FP_VN_VERTEX_NORMALS) {
		errorMessage = errorPrefix() + QString::fromLatin1("unknown action");
		return false;
	}
	QString err = run(*md.mm(), par, cb);
	if (!err.isEmpty()) {
		// meshlabserver prints the log, not errorMsg(): both get the message.
		errorMessage = err;
		VN_LOG(GLLogStream::WARNING, err.toStdString());
		return false;
	}
	return true;
}

#endif
