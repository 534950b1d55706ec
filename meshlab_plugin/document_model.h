#pragma once
//! The thermal model of a MeshLab document, shared by the C++17 core-call sources of the plugin
//! (core_calls.cpp, export_calls.cpp). Not for the C++14 sources that include MeshLab headers:
//! the thermal model's headers need C++17.
#include <string>
#include <vector>

#include "thermodec/mesh/mesh.h"
#include "thermodec/nodes/thermal_model.h"

namespace thermodec_meshlab {

//! The thermal model simulate_document builds from the document's mesh (face_node set for
//! every face) and an optional model file (empty: the core's bare-mesh defaults); see
//! core_calls.h for how document nodes are matched to model nodes. model_node[i] receives the
//! model node of document node i; description, one line on where the model came from.
//! \throw thermodec::InvalidInput (a face without node, an unreadable model file, a node the
//! model lacks), thermodec::IOError.
thermodec::ThermalModel document_model(const thermodec::Mesh& mesh, const std::vector<int>& node_ids,
                                       bool ids_index_model_nodes, const std::string& model_file,
                                       int rays_per_face, std::vector<int>& model_node,
                                       std::string& description);

}  // namespace thermodec_meshlab
