// Loads libfilter_vn.so the way MeshLab 2022.02+ does (QPluginLoader, the
// FilterPlugin IID, getMLVersion() against the running libmeshlab-common) and
// applies its filter to a small mesh: every method gives unit or zero normals,
// no NaN, zero for the isolated vertex and one only in a zero-area face; a bad method throws MLException.
//   load_filter_plugin PLUGIN.so   (exit status 0 when all pass)
#include <common/globals.h>
#include <common/mlexception.h>
#include <common/plugins/interfaces/filter_plugin.h>
#include <common/ml_document/mesh_document.h>

#include <QApplication>
#include <QPluginLoader>

#include <cmath>
#include <cstdio>

static int failures = 0;
static void check(bool ok, const char* what)
{
	std::printf("%s %s\n", ok ? "ok  " : "FAIL", what);
	if (!ok) ++failures;
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
	check(fp->filterName(a) == "Recompute Vertex Normals (vn)", "filter name");
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
	check(par.hasParameter("onlySelected") && !par.getBool("onlySelected"), "onlySelected, default off");
	check(par.hasParameter("faceNormals") && par.getBool("faceNormals"), "faceNormals, default on");
	for (int method = 0; method < 7; ++method) {
		par.setValue("method", IntValue(method));
		unsigned int mask = 0;
		bool ok = true;
		try {
			fp->applyFilter(a, par, md, mask, nullptr);
		} catch (const MLException& e) {
			std::printf("     %s\n", e.what());
			ok = false;
		}
		for (int i = 0; i < 4; ++i) {
			const Point3m& n = m->cm.vert[i].cN();
			ok = ok && std::isfinite(n[0]) && std::isfinite(n[1]) && std::isfinite(n[2]) && std::fabs(n.Norm() - 1) < 1e-6;
		}
		// 4 is isolated, 5 only in a zero-area face: both get the zero vector
		ok = ok && m->cm.vert[4].cN() == Point3m(0, 0, 0) && m->cm.vert[5].cN() == Point3m(0, 0, 0);
		char what[100];
		std::snprintf(what, sizeof what, "method %d: unit normals, isolated and degenerate-only vertices zero, no NaN", method);
		check(ok, what);
	}
	par.setValue("method", IntValue(99));
	bool threw = false;
	try {
		unsigned int mask = 0;
		fp->applyFilter(a, par, md, mask, nullptr);
	} catch (const MLException& e) {
		threw = QString(e.what()).contains("not one of 0..6");
	}
	check(threw, "method 99: MLException");
	std::printf("load_filter_plugin: %d failed\n", failures);
	return failures ? 1 : 0;
}
