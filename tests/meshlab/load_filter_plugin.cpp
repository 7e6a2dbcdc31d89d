// Loads libfilter_vn.so the way MeshLab 2022.02+ does (QPluginLoader, the
// FilterPlugin IID, getMLVersion() against the running libmeshlab-common) and
// applies its filter to a small mesh: every method gives unit normals, no NaN;
// the isolated vertex and one only in a zero-area face keep their normals; the
// name, the method labels and the help as the dialog shows them; "only
// selected" takes the vertices of selected faces and is on by default when
// something is selected; a layer without faces and a bad method throw MLException.
//   load_filter_plugin PLUGIN.so   (exit status 0 when all pass)
#include <common/globals.h>
#include <common/mlexception.h>
#include <common/plugins/interfaces/filter_plugin.h>
#include <common/ml_document/mesh_document.h>

#include <QApplication>
#include <QPluginLoader>
#include <QRegExp>

#include "vn.h"

#include <cmath>
#include <cstdio>
#include <vector>

static int failures = 0;
static void check(bool ok, const char* what)
{
	std::printf("%s %s\n", ok ? "ok  " : "FAIL", what);
	if (!ok) ++failures;
}

// Applies the filter: the message of the MLException it threw, or a null
// QString when it threw none.
static QString apply(FilterPlugin* fp, QAction* a, const RichParameterList& par, MeshDocument& md)
{
	try {
		unsigned int mask = 0;
		fp->applyFilter(a, par, md, mask, nullptr);
	} catch (const MLException& e) {
		std::printf("     %s\n", e.what());
		return QString::fromUtf8(e.what());
	}
	return QString();
}

int main(int argc, char** argv)
{
	QApplication app(argc, argv);
	if (argc < 2) return 2;
	QPluginLoader loader(QString::fromLocal8Bit(argv[1]));
	QObject* obj = loader.instance();
	check(obj != nullptr, "QPluginLoader loads the plugin");
	if (!obj) {
		std::printf("%s\n", qUtf8Printable(loader.errorString()));
		return 1;
	}
	check(loader.metaData().value("IID").toString() == QString(FILTER_PLUGIN_IID), "IID is vcg.meshlab.FilterPlugin/1.0");
	FilterPlugin* fp = qobject_cast<FilterPlugin*>(obj);
	check(fp != nullptr, "qobject_cast<FilterPlugin*>");
	if (!fp) return 1;
	std::pair<std::string, bool> v = fp->getMLVersion();
	check(v.first == meshlab::meshlabVersion() && v.second == meshlab::builtWithDoublePrecision(),
	      "getMLVersion() matches this MeshLab (version and scalar)");
	std::printf("     plugin built for MeshLab %s, %s\n", v.first.c_str(), v.second ? "double" : "float");
	check(fp->actions().size() == 1, "exactly one filter");
	QAction* a = fp->actions().front();
	check(fp->filterName(a) == "Re-Compute Vertex Normals (all published weightings)", "filter name");
	check(fp->getClass(a) == FilterPlugin::Normal, "class Normal (not Generic)");
	check((fp->postCondition(a) & MeshModel::MM_VERTNORMAL) != 0, "postcondition: vertex normals");

	MeshDocument md;
	MeshModel* m = md.addNewMesh("", "tetra");
	vcg::tri::Allocator<CMeshO>::AddVertices(m->cm, 6);
	const float p[6][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {5, 5, 5}, {0.5f, 0, 0}};
	for (int i = 0; i < 6; ++i) m->cm.vert[i].P() = Point3m(p[i][0], p[i][1], p[i][2]);
	const int f[5][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}, {0, 5, 1}};
	for (auto& t : f) vcg::tri::Allocator<CMeshO>::AddFace(m->cm, &m->cm.vert[t[0]], &m->cm.vert[t[1]], &m->cm.vert[t[2]]);

	RichParameterList par = fp->initParameterList(a, *m);
	check(par.hasParameter("method") && par.getEnum("method") == 1, "parameter method, default MWA (1)");
	check(par.hasParameter("weldByPosition") && !par.getBool("weldByPosition"), "weldByPosition, default off");
	check(par.hasParameter("onlySelected") && !par.getBool("onlySelected"), "onlySelected, default off (nothing selected)");
	{
		const RichEnum* e = dynamic_cast<const RichEnum*>(&par.getParameterByName("method"));
		bool ok = e && e->enumvalues.size() == static_cast<int>(vn_method_count) &&
		          e->enumvalues[1] == "Angle weighted (MWA, default)" &&
		          e->enumvalues[2] == "Sine and edge-length reciprocals (MWSELR, Max 1999)" &&
		          e->enumvalues[6].contains("not for shading") && e->enumvalues[6].contains("MEWCSA");
		for (int i = 0; ok && i < static_cast<int>(vn_method_count); ++i) ok = !e->enumvalues[i].contains("|E") && !e->enumvalues[i].contains("sin(");
		check(ok, "method labels in plain words with the acronym, MEWCSA not for shading");
		if (e)
			for (const QString& l : e->enumvalues) std::printf("     %s\n", qUtf8Printable(l));
		bool help = true;
		for (const char* n : {"method", "weldByPosition", "onlySelected", "faceNormals"}) {
			const QString t = par.getParameterByName(n).toolTip();
			help = help && !t.contains('\n') && !t.contains("|E");
			// no line wraps in the Help mode (test_meshlab.py says why)
			for (const QString& line : t.split("<br>")) help = help && QString(line).remove(QRegExp("<[^>]*>")).size() <= 44;
		}
		check(help, "parameter help in short <br>-separated lines, no paper notation");
	}
	check(par.hasParameter("faceNormals") && par.getBool("faceNormals"), "faceNormals, default on");
	const Point3m given4(0, 1, 0), given5(1, 0, 0);
	std::vector<Point3m> whole;
	for (int method = 0; method < 7; ++method) {
		par.setValue("method", IntValue(method));
		m->cm.vert[4].N() = given4;
		m->cm.vert[5].N() = given5;
		bool ok = apply(fp, a, par, md).isNull();
		for (int i = 0; i < 4; ++i) {
			const Point3m& n = m->cm.vert[i].cN();
			ok = ok && std::isfinite(n[0]) && std::isfinite(n[1]) && std::isfinite(n[2]) && std::fabs(n.Norm() - 1) < 1e-6;
		}
		// 4 is isolated, 5 only in a zero-area face: no face contributes, both keep theirs
		ok = ok && m->cm.vert[4].cN() == given4 && m->cm.vert[5].cN() == given5;
		char what[120];
		std::snprintf(what, sizeof what, "method %d: unit normals, isolated and degenerate-only vertices keep theirs, no NaN", method);
		check(ok, what);
		if (method == 1)
			for (int i = 0; i < 6; ++i) whole.push_back(m->cm.vert[i].cN());
	}

	// Face 1 (vertices 0, 1, 3) selected: "only selected" on by default; those
	// three get the whole-mesh normals, vertex 2 keeps its own.
	m->cm.face[1].SetS();
	m->cm.sfn = 1;
	{
		RichParameterList sp = fp->initParameterList(a, *m);
		check(sp.getBool("onlySelected"), "onlySelected, default on when a face is selected");
		const Point3m marker(0, 0, -1);
		for (int i = 0; i < 6; ++i) m->cm.vert[i].N() = marker;
		bool ok = apply(fp, a, sp, md).isNull();
		for (int i : {0, 1, 3}) ok = ok && (m->cm.vert[i].cN() - whole[i]).Norm() < 1e-6;
		for (int i : {2, 4, 5}) ok = ok && m->cm.vert[i].cN() == marker;
		check(ok && !m->cm.vert[0].IsS(), "selected face: its vertices get the whole-mesh normals, the others keep theirs, "
		                                  "MeshLab's selection unchanged");
	}

	// A layer with 960 points and no faces: refused, normals untouched.
	{
		MeshModel* cloud = md.addNewMesh("", "cloud");
		vcg::tri::Allocator<CMeshO>::AddVertices(cloud->cm, 960);
		for (int i = 0; i < 960; ++i) {
			cloud->cm.vert[i].P() = Point3m(i, 0, 0);
			cloud->cm.vert[i].N() = Point3m(0, 0, 1);
		}
		RichParameterList cp = fp->initParameterList(a, *cloud);
		const bool threw = apply(fp, a, cp, md).contains("needs faces: this layer has 960 vertices and no faces");
		bool kept = true;
		for (int i = 0; i < 960; ++i) kept = kept && cloud->cm.vert[i].cN() == Point3m(0, 0, 1);
		check(md.mm() == cloud && threw && kept, "960 points, no faces: MLException in the filter's words, normals kept");
		md.setCurrentMesh(m->id());
	}
	par.setValue("method", IntValue(99));
	check(apply(fp, a, par, md).contains(QString("not one of 0..%1").arg(static_cast<int>(vn_method_count) - 1)),
	      "method 99: MLException");
	std::printf("load_filter_plugin: %d failed\n", failures);
	return failures ? 1 : 0;
}
