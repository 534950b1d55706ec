#pragma once
//! The thermal model of a MeshLab document, shared by the C++17 core-call sources of the plugin
//! (core_calls.cpp, export_calls.cpp). Not for the C++14 sources that include MeshLab headers:
//! the thermal model's headers need C++17.
#include <string>
#include <vector>

#include "thermodec/mesh/mesh.h"
#include "thermodec/nodes/thermal_model.h"
#include "thermodec/thermal/simulation_cost.h"
#include "core_calls.h"

namespace thermodec_meshlab {

//! The thermal model simulate_document builds from the request: the document's mesh (face_node
//! set for every face), an optional model file (empty: the core's bare-mesh defaults), and the
//! request's rays_per_face and seed overrides; see core_calls.h for how document nodes are matched
//! to model nodes. One function for every filter, so that simulate, reduce, sensitivity and export
//! see the same model. model_node[i] receives the model node of document node i; description, one
//! line on where the model came from.
//! \throw thermodec::InvalidInput (a face without node, an unreadable model file, a node the
//! model lacks), thermodec::IOError.
thermodec::ThermalModel document_model(const DocumentModelRequest& request, std::vector<int>& model_node,
                                       std::string& description);

//! The core's cost refusal (thermodec::refuse_costly_run), before any work of every filter that
//! simulates. No override in the filters: MeshLab 2020.09 cannot cancel a running filter, and a
//! meshlabserver script must list every parameter of its filter (a new one would break the
//! scripts users have); the CLI's --force runs such a model.
void refuse_costly(const thermodec::SimulationCostCheck& check);

}  // namespace thermodec_meshlab
