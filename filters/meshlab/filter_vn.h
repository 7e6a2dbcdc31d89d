/*
 * MeshLab filter plugin: "Re-Compute Vertex Normals (all published
 * weightings)", every weighting
 * scheme of the vn library (Jin, Lewis & West 2005), computed in double
 * precision by the library. One source for MeshLab 2020.09 and 2022.02+
 * (see meshlab_compat.h).
 */
#ifndef VN_FILTER_VN_H
#define VN_FILTER_VN_H

#include "meshlab_compat.h"

#include <memory>
#include <mutex>

class FilterVnPlugin : public QObject, public VnFilterBase
{
	Q_OBJECT
#if VN_MESHLAB_API >= 2022
	MESHLAB_PLUGIN_IID_EXPORTER(FILTER_PLUGIN_IID)
	Q_INTERFACES(FilterPlugin)
#else
	MESHLAB_PLUGIN_IID_EXPORTER(MESH_FILTER_INTERFACE_IID)
	Q_INTERFACES(MeshFilterInterface)
#endif

public:
	enum { FP_VN_VERTEX_NORMALS };

	FilterVnPlugin();
	~FilterVnPlugin() override;

	QString pluginName() const override;
	QString filterName(VnActionID filter) const override;
	QString filterInfo(VnActionID filter) const override;
	FilterClass getClass(VN_ACTION* a) VN_CONST_2022 override;
	VnFilterArity filterArity(VN_ACTION* a) const override;
	int getPreConditions(VN_ACTION* a) const override;
	int postCondition(VN_ACTION* a) const override;

#if VN_MESHLAB_API >= 2022
	RichParameterList initParameterList(const QAction* a, const MeshModel& m) override;
	std::map<std::string, QVariant> applyFilter(const QAction* a, const RichParameterList& par, MeshDocument& md,
	                                            unsigned int& postConditionMask, vcg::CallBackPos* cb) override;
#else
	void initParameterSet(QAction* a, MeshModel& m, RichParameterList& par) override;
	bool applyFilter(QAction* a, MeshDocument& md, const RichParameterList& par, vcg::CallBackPos* cb) override;
#endif

private:
	/* somethingSelected: the default of "Affect only selected vertices". */
	void fillParameters(RichParameterList& par, bool somethingSelected) const;
	/* Computes and writes the normals; returns an empty string on success,
	 * else the error message (nothing in the mesh changed). */
	QString run(MeshModel& m, const RichParameterList& par, vcg::CallBackPos* cb);

	struct Work; /* work arrays kept between calls (filter_vn.cpp) */
	QString compute(MeshModel& m, const RichParameterList& par, vcg::CallBackPos* cb, Work& w);
	std::unique_ptr<Work> work;
	std::mutex workMutex;
};

#endif
