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

#include <map>
#include <string>
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
  FaceQuality,  //!< the current layer's per-face node ids (face quality, or a thermodec result
                //!< layer's own per-face ids)
  Layers,       //!< several layers, each one node (the paper's one-file-per-cluster layout)
};

//! A thermodec mesh gathered from the document, with the way back.
struct DocumentMesh {
  thermodec::Mesh mesh;
  std::vector<FaceOrigin> origin;  //!< #F: origin of each gathered face
  //! #nodes: the document's id of node i (the face-quality value, or the layer's id).
  std::vector<int> node_ids;
  NodeSource source = NodeSource::None;
  MeshModel* layer = nullptr;      //!< FaceQuality: the layer the nodes were read from
};

// --- What the plugin knows about layers -----------------------------------------------------
// Stored as vcg per-mesh / per-face attributes of the layer's CMeshO: they live as long as the
// layer since MeshLab started (saved files carry node ids in face quality and names in the
// PLY header instead).

//! Marks `layer` as made by a thermodec filter from `source` (`what`: "temperature",
//! "reduced", ...): it is never taken for a node, and it inherits the source's node names,
//! file (for output folders and the model file search) and model file.
void tag_result_layer(MeshModel& layer, const std::string& what, MeshModel& source);
//! Whether a thermodec filter made `layer` (tag_result_layer).
bool is_result_layer(MeshModel& layer);
//! Stores each face's document node id in `layer` itself (a per-face attribute), for a result
//! layer whose face quality holds something else (temperatures). \pre ids.size() == live faces.
void set_layer_node_ids(MeshModel& layer, const std::vector<int>& ids);
//! The names of node ids: the layer's own (set_node_names, or inherited from its source), else
//! those in its PLY file's header (`comment thermodec node <id> <name>`, as `thermodec convert`
//! writes them). Ids without a name are absent.
std::map<int, std::string> node_names_of(MeshModel& layer);
void set_node_names(MeshModel& layer, const std::map<int, std::string>& names);
//! The file `layer` came from, or for a result layer its source's; empty if none.
QString layer_file(MeshModel& layer);
//! The model file last used with `layer` (or its source); empty if none.
QString layer_model_file(MeshModel& layer);
void set_layer_model_file(MeshModel& layer, const QString& path);
//! Hides `layer` (in the GUI's layer dialog and view), e.g. the input of a result layer.
void hide_layer(MeshDocument& md, MeshModel& layer);

//! The live vertices and faces of one layer as a thermodec mesh with face_node = -1,
//! face_material = -1, face_back_material = -1 (one-sided).
//! \throw thermodec::InvalidInput if the layer has no live face.
DocumentMesh mesh_from_layer(MeshModel& layer);

//! The document's nodal breakdown, never taken from a layer a thermodec filter made unless it
//! is the current one: (1) the current layer's own per-face ids (a thermodec result layer);
//! (2) the current layer's per-face quality holding node ids (integers >= 0; ids need not be
//! contiguous), named by node_names_of (else "node_<id>"); (3) without either, every layer not
//! made by thermodec is one node named after its label (without a .ply/.obj/.stl/.off
//! extension), when there are at least two.
//! \throw thermodec::InvalidInput on an empty document or layer, no nodes ("run Thermal: assign
//! nodes first"), or a quality that is not a non-negative integer (naming the face).
DocumentMesh mesh_with_nodes(MeshDocument& md);

//! The current layer with its nodes when its face quality holds node ids (as
//! mesh_with_nodes), else the bare layer (face_node = -1, source None). For filters that work
//! with or without nodes. \throw thermodec::InvalidInput as mesh_with_nodes.
DocumentMesh mesh_with_optional_nodes(MeshDocument& md);

//! Adds `mesh` (whose face_node indexes dm's nodes, or is -1) to the document as new layers
//! tagged as results (tag_result_layer) and returns them. Layers source: one layer per node,
//! labelled "<node name> <suffix>". Otherwise one layer "<current layer name> <suffix>" (the
//! label ends in ".ply" so that MeshLab's layer list, which drops the last extension, shows it
//! whole); with nodes, its face quality holds the document's node id (dm.node_ids[face_node])
//! and faces are coloured per node. The input layer(s) are hidden and the (first) new layer
//! becomes the current one (what meshlabserver -o saves).
//! \throw thermodec::InvalidInput if `mesh` has no face.
std::vector<MeshModel*> add_layers(MeshDocument& md, const DocumentMesh& dm,
                                   const thermodec::Mesh& mesh, const QString& suffix);

//! A layer's name without a mesh-file extension ("satellite.ply" -> "satellite").
QString layer_stem(const MeshModel& layer);
//! The name a result of `layer` starts with: the layer's stem, or for a layer a Thermal filter
//! made, the stem of the file its nodes came from.
QString result_stem(MeshModel& layer);
//! A result label MeshLab's layer list shows whole: `text` + ".ply" (the list drops the last
//! extension, so without it "... 206.93 K" would show as "... 206").
QString result_label(const QString& text);

//! Per node i, a distinct colour (vcg's scatter palette over node_count hues).
vcg::Color4b node_color(int node, int node_count);

//! Writes `value[f]` into the quality of gathered face f, enabling face quality on each
//! touched layer. \pre value.size() == dm.origin.size().
void set_face_quality(const DocumentMesh& dm, const std::vector<double>& value);

//! Colours gathered face f with node_color(dm.mesh.face_node[f], dm.mesh.node_names.size()),
//! enabling face colour on each touched layer.
void paint_nodes(const DocumentMesh& dm);

}  // namespace thermodec_meshlab
