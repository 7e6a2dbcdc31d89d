/*
 * The few differences between the two MeshLab plugin SDKs the vn filter is
 * built against, so that filter_vn.h/.cpp are one source for both:
 *
 *  - MeshLab 2020.09 (Debian bookworm; CMake sets VN_MESHLAB_API=2020):
 *    MeshFilterInterface from <common/interfaces.h>, IID
 *    "vcg.meshlab.MeshFilterInterface/1.0"; non-const QAction*; parameters
 *    filled into a RichParameterList&; applyFilter returns bool and reports
 *    errors through errorMessage; logging with Log().
 *  - MeshLab 2022.02+ (Debian trixie; VN_MESHLAB_API=2022): FilterPlugin
 *    from <common/plugins/interfaces/filter_plugin.h>, IID
 *    "vcg.meshlab.FilterPlugin/1.0"; const QAction*; initParameterList
 *    returns the list; applyFilter returns a map of outputs and reports errors
 *    by throwing MLException; logging with log(). MESHLAB_PLUGIN_IID_EXPORTER
 *    adds getMLVersion() (the version and scalar type MeshLab checks at load).
 *
 * Both need MESHLAB_SCALAR (float in Debian's builds) defined on the command line.
 */
#ifndef VN_MESHLAB_COMPAT_H
#define VN_MESHLAB_COMPAT_H

#if !defined(VN_MESHLAB_API)
#  error "VN_MESHLAB_API must be 2020 or 2022 (set by filters/meshlab/CMakeLists.txt)"
#endif

#if VN_MESHLAB_API >= 2022
#  include <common/plugins/interfaces/filter_plugin.h>
#  include <common/mlexception.h>
typedef FilterPlugin VnFilterBase;
#  define VN_FILTER_IID FILTER_PLUGIN_IID
#  define VN_ACTION const QAction
#  define VN_CONST_2022 const
typedef FilterPlugin::FilterArity VnFilterArity;
typedef MeshLabPlugin::ActionIDType VnActionID;
#  define VN_LOG log
#else
#  include <common/interfaces.h>
typedef MeshFilterInterface VnFilterBase;
#  define VN_FILTER_IID MESH_FILTER_INTERFACE_IID
#  define VN_ACTION QAction
#  define VN_CONST_2022
typedef MeshFilterInterface::FILTER_ARITY VnFilterArity;
typedef MeshCommonInterface::FilterIDType VnActionID;
#  define VN_LOG Log
#endif

#endif
