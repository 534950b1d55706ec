#pragma once
//! Conversion between MeshLab's document (CMeshO layers) and thermodec's one shared Mesh. No
//! algorithm lives here: the filters gather a thermodec::Mesh, call the core, and scatter the
//! per-face results back onto the faces they came from.
//!
//! Coordinates are each layer's vertex coordinates; layer matrices (cm.Tr, e.g. from an .mlp)
//! are not applied, and new layers inherit their source layer's matrix, so a result sits where
//! its input is drawn. Layers of one document must therefore share one frame.
//!
//! Units: MeshLab coordinates are taken as metres (thermodec's unit); scale the layer first
//! (Filters > Normals, Curvatures and Orientation > Transform: Scale) if the file is in mm.
#include <common/meshmodel.h>

#include <vector>

#include "thermodec/mesh/mesh.h"

namespace thermodec_meshlab {

//! Where a face of the gathered thermodec::Mesh lives in the document.
struct FaceOrigin {
  MeshModel* layer;  //!< the layer holding the face
  int face;          //!< index into layer->cm.face (deleted faces are never gathered)
};

//! How the document encodes thermal nodes.
enum class NodeSource {
  None,         //!< nodes not read (face_node = -1)
  FaceQuality,  //!< one layer, per-face quality = node id (integer >= 0)
  Layers,       //!< several layers, each one node (the paper's one-file-per-cluster layout)
};

//! A thermodec mesh gathered from the document, with the way back.
struct DocumentMesh {
  thermodec::Mesh mesh;
  std::vector<FaceOrigin> origin;  //!< #F: origin of each gathered face
  //! #nodes: the document's id of node i (the face-quality value, or the layer's id).
  std::vector<int> node_ids;
  NodeSource source = NodeSource::None;
};

//! The live vertices and faces of one layer as a thermodec mesh with face_node = -1,
//! face_material = -1, face_back_material = -1 (one-sided).
//! \throw thermodec::InvalidInput if the layer has no live face.
DocumentMesh mesh_from_layer(MeshModel& layer);

//! The document's nodal breakdown: with more than one mesh layer, every layer is one node
//! named after its label (without a .ply/.obj/.stl/.off extension); with one layer, the
//! current layer's per-face quality holds node ids (integers >= 0, named "node_<id>"; ids need
//! not be contiguous).
//! \throw thermodec::InvalidInput on an empty document or layer, a single layer without face
//! quality ("no nodes: run Thermal: assign nodes first"), or a quality that is not a
//! non-negative integer (naming the face).
DocumentMesh mesh_with_nodes(MeshDocument& md);

//! The current layer with its nodes when its face quality holds node ids (as
//! mesh_with_nodes), else the bare layer (face_node = -1, source None). For filters that work
//! with or without nodes. \throw thermodec::InvalidInput as mesh_with_nodes.
DocumentMesh mesh_with_optional_nodes(MeshDocument& md);

//! Adds `mesh` (whose face_node indexes dm's nodes, or is -1) to the document as new layers
//! and returns them. Layers source: one layer per node, labelled "<node name> <suffix>".
//! Otherwise one layer "<current layer> <suffix>"; with nodes, its face quality holds the
//! document's node id (dm.node_ids[face_node]) and faces are coloured per node.
//! The (first) new layer becomes the current one (what meshlabserver -o saves).
//! \throw thermodec::InvalidInput if `mesh` has no face.
std::vector<MeshModel*> add_layers(MeshDocument& md, const DocumentMesh& dm,
                                   const thermodec::Mesh& mesh, const QString& suffix);

//! Per node i, a distinct colour (vcg's scatter palette over node_count hues).
vcg::Color4b node_color(int node, int node_count);

//! Writes `value[f]` into the quality of gathered face f, enabling face quality on each
//! touched layer. \pre value.size() == dm.origin.size().
void set_face_quality(const DocumentMesh& dm, const std::vector<double>& value);

//! Colours gathered face f with node_color(dm.mesh.face_node[f], dm.mesh.node_names.size()),
//! enabling face colour on each touched layer.
void paint_nodes(const DocumentMesh& dm);

}  // namespace thermodec_meshlab
