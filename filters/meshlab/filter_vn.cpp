/*
 * "Recompute Vertex Normals (vn)": MeshLab's vertex normals from the vn
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

QString methodLabel(int i)
{
	return QString::fromLatin1(vn_method_name(static_cast<vn_method>(i))).toUpper();
}

QString methodTooltip()
{
	QString t = QString::fromLatin1("How each face around a vertex weighs in its normal "
	                                "(Jin, Lewis & West 2005):");
	for (int i = 0; i < static_cast<int>(vn_method_count); ++i) {
		vn_method m = static_cast<vn_method>(i);
		t += QString::fromLatin1("\n%1: %2 [%3]")
		         .arg(methodLabel(i), QString::fromLatin1(vn_method_description(m)),
		              QString::fromLatin1(vn_method_reference(m)));
	}
	return t;
}

bool finite3(const double* v)
{
	return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
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
	case FP_VN_VERTEX_NORMALS: return QString::fromLatin1("Recompute Vertex Normals (vn)");
	default: return QString();
	}
}

QString FilterVnPlugin::filterInfo(VnActionID filter) const
{
	switch (filter) {
	case FP_VN_VERTEX_NORMALS: {
		QString s = QString::fromLatin1(
		    "Recomputes the per-vertex normals with any of the seven weighting schemes compared by "
		    "Jin, Lewis and West, computed in double precision by the vn library %1 "
		    "(faces that are degenerate contribute nothing; a vertex that no face contributes to "
		    "gets the zero normal).<br><br>")
		                .arg(QString::fromLatin1(vn_version_string()));
		for (int i = 0; i < static_cast<int>(vn_method_count); ++i) {
			vn_method m = static_cast<vn_method>(i);
			s += QString::fromLatin1("<b>%1</b>: %2 [%3]<br>")
			         .arg(methodLabel(i), QString::fromLatin1(vn_method_description(m)).toHtmlEscaped(),
			              QString::fromLatin1(vn_method_reference(m)).toHtmlEscaped());
		}
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

void FilterVnPlugin::fillParameters(RichParameterList& par) const
{
	QStringList methods;
	for (int i = 0; i < static_cast<int>(vn_method_count); ++i)
		methods << methodLabel(i);
	par.addParam(RichEnum(QString::fromLatin1(kMethod), static_cast<int>(vn_method_mwa), methods,
	                      QString::fromLatin1("Weighting scheme"), methodTooltip()));
	par.addParam(RichBool(QString::fromLatin1(kWeld), false, QString::fromLatin1("Weld by position"),
	                      QString::fromLatin1("Treat vertices at exactly the same position (split by seams or "
	                                          "by the file) as one while computing, and give every copy "
	                                          "the same normal. The mesh itself is not changed.")));
	par.addParam(RichBool(QString::fromLatin1(kSelected), false, QString::fromLatin1("Affect only selected vertices"),
	                      QString::fromLatin1("Write the new normal only to the selected vertices (it is computed "
	                                          "from all the faces around them); the others keep theirs.")));
	par.addParam(RichBool(QString::fromLatin1(kFaceNormals), true, QString::fromLatin1("Recompute face normals"),
	                      QString::fromLatin1("Also recompute the (unit) face normals.")));
}

QString FilterVnPlugin::run(MeshModel& mm, const RichParameterList& par, vcg::CallBackPos* cb)
{
	CMeshO& m = mm.cm;
	const int methodIndex = par.getEnum(QString::fromLatin1(kMethod));
	if (methodIndex < 0 || methodIndex >= static_cast<int>(vn_method_count) ||
	    !vn_method_name(static_cast<vn_method>(methodIndex)))
		return QString::fromLatin1("Recompute Vertex Normals (vn): method %1 is not one of 0..%2 (%3)")
		    .arg(methodIndex)
		    .arg(static_cast<int>(vn_method_count) - 1)
		    .arg(QStringList([] {
			         QStringList l;
			         for (int i = 0; i < static_cast<int>(vn_method_count); ++i) l << methodLabel(i);
			         return l;
		         }())
		             .join(QString::fromLatin1(", ")));
	const vn_method method = static_cast<vn_method>(methodIndex);
	const bool weld = par.getBool(QString::fromLatin1(kWeld));
	const bool onlySelected = par.getBool(QString::fromLatin1(kSelected));
	const bool faceNormals = par.getBool(QString::fromLatin1(kFaceNormals));

	// Live vertices, numbered densely; positions as double (exact).
	std::vector<uint32_t> number(m.vert.size(), UINT32_MAX);
	std::vector<double> positions;
	positions.reserve(3 * static_cast<size_t>(m.vn));
	uint32_t count = 0;
	for (size_t i = 0; i < m.vert.size(); ++i) {
		if (m.vert[i].IsD()) continue;
		if (count == UINT32_MAX) return QString::fromLatin1("Recompute Vertex Normals (vn): too many vertices");
		number[i] = count++;
		const auto& p = m.vert[i].cP();
		positions.push_back(static_cast<double>(p[0]));
		positions.push_back(static_cast<double>(p[1]));
		positions.push_back(static_cast<double>(p[2]));
	}
	std::vector<uint32_t> indices;
	indices.reserve(3 * static_cast<size_t>(m.fn));
	for (auto fi = m.face.begin(); fi != m.face.end(); ++fi) {
		if (fi->IsD()) continue;
		for (int k = 0; k < 3; ++k) {
			const size_t v = static_cast<size_t>(vcg::tri::Index(m, fi->cV(k)));
			if (v >= number.size() || number[v] == UINT32_MAX)
				return QString::fromLatin1("Recompute Vertex Normals (vn): a face uses a deleted vertex");
			indices.push_back(number[v]);
		}
	}
	if (cb) cb(10, "vn: mesh read");

	vn_positions pos = {positions.data(), count, 0, vn_scalar_float64};
	vn_options options = {};
	options.threads = std::thread::hardware_concurrency();
	std::vector<uint32_t> remap;
	if (weld) {
		remap.resize(count);
		vn_result r = vn_weld_positions(remap.data(), &pos, 0.0, &options);
		if (r != vn_result_success)
			return QString::fromLatin1("Recompute Vertex Normals (vn): welding failed: %1")
			    .arg(QString::fromLatin1(vn_result_string(r)));
		for (uint32_t& i : indices) i = remap[i];
	}
	std::vector<double> normals(3 * static_cast<size_t>(count));
	vn_vectors out = {normals.data(), 0, vn_scalar_float64};
	vn_stats stats = {};
	vn_result r = vn_triangle_normals(&out, &pos, indices.data(), indices.size(), method, &options, &stats);
	if (r != vn_result_success)
		return QString::fromLatin1("Recompute Vertex Normals (vn): %1").arg(QString::fromLatin1(vn_result_string(r)));
	if (cb) cb(80, "vn: normals computed");

	// Write back. vn never returns NaN; a non-finite value is turned into zero
	// all the same, so that MeshLab never sees one.
	size_t written = 0, zero = 0;
	for (size_t i = 0; i < m.vert.size(); ++i) {
		if (number[i] == UINT32_MAX) continue;
		CVertexO& v = m.vert[i];
		if (onlySelected && !v.IsS()) continue;
		const uint32_t src = weld ? remap[number[i]] : number[i];
		const double* n = &normals[3 * static_cast<size_t>(src)];
		if (finite3(n) && (n[0] != 0 || n[1] != 0 || n[2] != 0))
			v.N() = CVertexO::NormalType(static_cast<Scalarm>(n[0]), static_cast<Scalarm>(n[1]), static_cast<Scalarm>(n[2]));
		else {
			v.N() = CVertexO::NormalType(0, 0, 0);
			++zero;
		}
		++written;
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
	VN_LOG("vn %s: %zu vertex normals written, %zu zero (no face contributes), %zu of %zu faces degenerate%s",
	       vn_method_name(method), written, zero, stats.degenerate_faces, stats.faces, weld ? ", welded by position" : "");
	if (cb) cb(100, "vn: done");
	return QString();
}

#if VN_MESHLAB_API >= 2022

RichParameterList FilterVnPlugin::initParameterList(const QAction* a, const MeshModel&)
{
	RichParameterList par;
	if (ID(a) == FP_VN_VERTEX_NORMALS) fillParameters(par);
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

void FilterVnPlugin::initParameterSet(QAction* a, MeshModel&, RichParameterList& par)
{
	if (ID(a) == FP_VN_VERTEX_NORMALS) fillParameters(par);
}

bool FilterVnPlugin::applyFilter(QAction* a, MeshDocument& md, const RichParameterList& par, vcg::CallBackPos* cb)
{
	if (ID(a) != FP_VN_VERTEX_NORMALS) {
		errorMessage = QString::fromLatin1("Recompute Vertex Normals (vn): unknown action");
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
