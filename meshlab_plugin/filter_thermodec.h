#pragma once
//! thermodec's MeshLab 2020.09 filter plugin. Each filter reads its parameters, gathers the
//! document into a thermodec::Mesh (document_mesh.h), calls one core function and writes the
//! result back (face quality, colours, new layers, files) — the algorithms stay in the core.
//! A filter is compiled in only when its core function exists (THERMODEC_FILTER_<ID>, set by
//! meshlab_plugin/CMakeLists.txt).
#include <common/interfaces.h>

class ThermodecFilterPlugin : public QObject, public MeshFilterInterface {
  Q_OBJECT
  MESHLAB_PLUGIN_IID_EXPORTER(MESH_FILTER_INTERFACE_IID)
  Q_INTERFACES(MeshFilterInterface)

 public:
  enum FilterId {
    FP_ASSIGN_NODES,
    FP_EXTRACT_EXTERNAL,
    FP_DECIMATE_RATIO,
    FP_SIMULATE,
    FP_SENSITIVITY,
    FP_REDUCE,
    FP_EXPORT,  // filter_export.cpp
  };

  ThermodecFilterPlugin();

  // The QAction* overloads of the base class stay visible next to the overrides below.
  using MeshFilterInterface::filterInfo;
  using MeshFilterInterface::filterName;

  QString pluginName() const override;
  QString filterName(FilterIDType filter) const override;
  QString filterInfo(FilterIDType filter) const override;
  FilterClass getClass(QAction* action) override;
  FILTER_ARITY filterArity(QAction* action) const override;
  int getRequirements(QAction* action) override;
  int getPreConditions(QAction* action) const override;
  int postCondition(QAction* action) const override;
  void initParameterSet(QAction* action, MeshModel& m, RichParameterList& params) override;
  bool applyFilter(QAction* action, MeshDocument& md, const RichParameterList& params,
                   vcg::CallBackPos* cb) override;

 private:
  bool assign_nodes(MeshDocument& md, const RichParameterList& params, vcg::CallBackPos* cb);
  bool extract_external(MeshDocument& md, const RichParameterList& params, vcg::CallBackPos* cb);
  bool decimate_ratio(MeshDocument& md, const RichParameterList& params, vcg::CallBackPos* cb);
  bool simulate(MeshDocument& md, const RichParameterList& params, vcg::CallBackPos* cb);
  bool sensitivity(MeshDocument& md, const RichParameterList& params, vcg::CallBackPos* cb);
  bool reduce(MeshDocument& md, const RichParameterList& params, vcg::CallBackPos* cb);
  // "Thermal: export for other tools", in filter_export.cpp.
  QString export_info() const;
  void export_parameters(MeshModel& m, RichParameterList& params) const;
  bool export_for_tools(MeshDocument& md, const RichParameterList& params, vcg::CallBackPos* cb);
};
