/*
 * "Re-Compute Vertex Normals (all published weightings)": MeshLab's vertex
 * normals from the vn
 * library. The plugin only moves data: MeshLab's live vertices and faces into
 * vn's arrays (positions widened to double), vn_weld_positions and
 * vn_triangle_normals, and the result back into the mesh. No weighting
 * scheme is implemented here.
 */
#include "filter_vn.h"

#include <vn.h>

#include <cmath>
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
	const char* help;    /* one short line for the parameter's help */
	const char* info;    /* the filter's description */
};
const MethodWords kMethods[] = {
    {"MWE", "Equal weights (MWE, Gouraud 1971)", "every face counts the same",
     "every face around the vertex counts the same, whatever its size or shape (Gouraud 1971)."},
    {"MWA", "Angle weighted (MWA, default)", "each face by its angle at the vertex (recommended)",
     "each face counts by its corner angle at the vertex (Thurmer and Wuthrich 1998). Recommended "
     "for shading: it depends least on how the surface is cut into triangles."},
    {"MWSELR", "Sine and edge-length reciprocals (MWSELR, Max 1999)",
     "angle sine over the two edge lengths",
     "each face counts by the sine of its corner angle divided by the lengths of the two edges "
     "that meet at the vertex (Max 1999): exact on a sphere."},
    {"MWAAT", "Area weighted (MWAAT, Max 1999)", "each face by its area",
     "each face counts by its area: big faces count more (Max 1999)."},
    {"MWELR", "Edge-length reciprocals (MWELR, Max 1999)", "one over the two edge lengths",
     "each face counts by one over the product of the lengths of its two edges that meet at the "
     "vertex: short edges count more (Max 1999)."},
    {"MWRELR", "Square roots of edge-length reciprocals (MWRELR, Max 1999)",
     "one over the square root of the two edge lengths",
     "as the previous one, with the square root of the product of the two edge lengths (Max 1999)."},
    {"MEWCSA", "Cotangent weights, not for shading (MEWCSA, Desbrun 1999)",
     "cotangents of the opposite angles; not for shading",
     "each edge counts by the cotangents of the two angles opposite it: the direction in which "
     "the surface area grows (Desbrun et al. 1999). <b>Not for shading</b>: its sign is not "
     "corrected, so where the surface curves the other way the normal points inwards (on the "
     "Stanford bunny about one normal in three is more than 90 degrees from MWA), which renders "
     "as black streaks."},
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
	t += QString::fromLatin1("<br>The filter's description above says more.");
	return t;
}

// Below this many vertices vn runs on the calling thread.
const uint32_t kThreadMinVertices = 200000;

QString errorPrefix()
{
	return QString::fromLatin1(kFilterName) + QString::fromLatin1(": ");
}

bool usable3(const double* v)
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
	case FP_VN_VERTEX_NORMALS: {
		QString s = QString::fromLatin1(
		    "Recomputes the per-vertex normals with any of the seven ways of weighting the faces "
		    "around a vertex that Jin, Lewis and West compared, computed in double precision by the vn "
		    "library %1.<br>"
		    "A vertex that no face contributes to (a loose point, or one whose faces all have zero "
		    "area) keeps the normal it has (MeshLab's own Re-Compute Vertex Normals, too, leaves loose "
		    "points alone). A layer without faces is refused.<br><br>")
		                .arg(QString::fromLatin1(vn_version_string()));
		for (int i = 0; i < static_cast<int>(vn_method_count); ++i)
			s += QString::fromLatin1("<b>%1</b>: %2<br>")
			         .arg(QString::fromLatin1(kMethods[i].label).toHtmlEscaped(), QString::fromLatin1(kMethods[i].info));
		s += QString::fromLatin1("<br>See: <i>Shuangshuang Jin, Robert R. Lewis, David West</i><br>"
		                         "<b>\"A comparison of algorithms for vertex normal computation\"</b><br>"
		                         "The Visual Computer 21, 71-82 (2005).");
		return s;
	}
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
	                      QString::fromLatin1("Vertices at the same position (split by seams)<br>"
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

QString FilterVnPlugin::run(MeshModel& mm, const RichParameterList& par, vcg::CallBackPos* cb)
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

	size_t liveFaces = 0;
	for (auto fi = m.face.begin(); fi != m.face.end(); ++fi)
		if (!fi->IsD()) ++liveFaces;
	if (liveFaces == 0) {
		size_t liveVerts = 0;
		for (size_t i = 0; i < m.vert.size(); ++i)
			if (!m.vert[i].IsD()) ++liveVerts;
		return QString::fromLatin1("%1 needs faces: this layer has %2 vertices and no faces; its normals "
		                           "are left as they are")
		    .arg(QString::fromLatin1(kFilterName))
		    .arg(liveVerts);
	}

	// Live vertices, numbered densely; positions as double (exact).
	std::vector<uint32_t> number(m.vert.size(), UINT32_MAX);
	std::vector<double> positions;
	positions.reserve(3 * static_cast<size_t>(m.vn));
	uint32_t count = 0;
	for (size_t i = 0; i < m.vert.size(); ++i) {
		if (m.vert[i].IsD()) continue;
		if (count == UINT32_MAX) return errorPrefix() + QString::fromLatin1("too many vertices");
		number[i] = count++;
		const auto& p = m.vert[i].cP();
		positions.push_back(static_cast<double>(p[0]));
		positions.push_back(static_cast<double>(p[1]));
		positions.push_back(static_cast<double>(p[2]));
	}
	// With "only selected": the selected vertices and the vertices of the
	// selected faces (MeshLab's rectangle selection selects faces). MeshLab's
	// selection flags are left as they are.
	std::vector<char> chosen;
	if (onlySelected) {
		chosen.assign(m.vert.size(), 0);
		for (size_t i = 0; i < m.vert.size(); ++i)
			if (!m.vert[i].IsD() && m.vert[i].IsS()) chosen[i] = 1;
	}
	std::vector<uint32_t> indices;
	indices.reserve(3 * liveFaces);
	for (auto fi = m.face.begin(); fi != m.face.end(); ++fi) {
		if (fi->IsD()) continue;
		for (int k = 0; k < 3; ++k) {
			const size_t v = static_cast<size_t>(vcg::tri::Index(m, fi->cV(k)));
			if (v >= number.size() || number[v] == UINT32_MAX)
				return errorPrefix() + QString::fromLatin1("a face uses a deleted vertex");
			indices.push_back(number[v]);
			if (onlySelected && fi->IsS()) chosen[v] = 1;
		}
	}
	// Progress only where it can be seen: a call on a small mesh takes about
	// a millisecond, and each report costs the GUI an event loop pass.
	if (!(count >= kThreadMinVertices)) cb = nullptr;
	if (cb) cb(10, "vn: mesh read");

	vn_positions pos = {positions.data(), count, 0, vn_scalar_float64};
	vn_options options = {};
	// Threads pay off only on large meshes: starting them costs more than the
	// bunny's (35k vertices) whole computation.
	options.threads = count >= kThreadMinVertices ? std::thread::hardware_concurrency() : 1;
	std::vector<uint32_t> remap;
	if (weld) {
		remap.resize(count);
		vn_result r = vn_weld_positions(remap.data(), &pos, 0.0, &options);
		if (r != vn_result_success)
			return errorPrefix() + QString::fromLatin1("welding failed: %1").arg(QString::fromLatin1(vn_result_string(r)));
		for (uint32_t& i : indices) i = remap[i];
	}
	std::vector<double> normals(3 * static_cast<size_t>(count));
	vn_vectors out = {normals.data(), 0, vn_scalar_float64};
	vn_stats stats = {};
	vn_result r = vn_triangle_normals(&out, &pos, indices.data(), indices.size(), method, &options, &stats);
	if (r != vn_result_success)
		return errorPrefix() + QString::fromLatin1(vn_result_string(r));
	if (cb) cb(80, "vn: normals computed");

	// Write back. A vertex that no face contributes to (vn gives it the zero
	// vector: no face, or only zero-area ones) keeps its normal: the filter
	// never overwrites a normal it did not compute. vn never returns NaN; a
	// non-finite value would be treated the same.
	size_t changed = 0, kept = 0, considered = 0;
	for (size_t i = 0; i < m.vert.size(); ++i) {
		if (number[i] == UINT32_MAX) continue;
		if (onlySelected && !chosen[i]) continue;
		++considered;
		CVertexO& v = m.vert[i];
		const uint32_t src = weld ? remap[number[i]] : number[i];
		const double* n = &normals[3 * static_cast<size_t>(src)];
		if (usable3(n)) {
			v.N() = CVertexO::NormalType(static_cast<Scalarm>(n[0]), static_cast<Scalarm>(n[1]), static_cast<Scalarm>(n[2]));
			++changed;
		} else
			++kept;
	}
	if (faceNormals) {
		vcg::tri::UpdateNormal<CMeshO>::PerFaceNormalized(m);
		for (auto fi = m.face.begin(); fi != m.face.end(); ++fi) {
			if (fi->IsD()) continue;
			const auto& n = fi->cN();
			if (!std::isfinite(n[0]) || !std::isfinite(n[1]) || !std::isfinite(n[2]))
				fi->N() = CFaceO::NormalType(0, 0, 0);
		}
	}
	const QString msg =
	    QString::fromLatin1("%1, %2: %3 of %4 vertex normals changed%5, %6 kept (no face contributes); "
	                        "%7 of %8 faces degenerate%9")
	        .arg(QString::fromLatin1(kFilterName), methodAcronym(methodIndex))
	        .arg(changed)
	        .arg(count)
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
