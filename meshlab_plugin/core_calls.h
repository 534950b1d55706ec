#pragma once
//! Core calls whose headers need C++17 (std::filesystem, std::optional in the thermal model),
//! behind an interface the C++14 plugin sources can include: only thermodec::Mesh, strings and
//! vectors cross it. Compiled as C++17 without any MeshLab header.
#include <functional>
#include <string>
#include <vector>

#include "thermodec/mesh/mesh.h"

namespace thermodec_meshlab {

//! What the document asks of a core call: its mesh and nodes, the model file and overrides.
struct DocumentModelRequest {
  const thermodec::Mesh* mesh = nullptr;  //!< document mesh, face_node set for every face
  std::vector<int> node_ids;
  bool ids_index_model_nodes = false;
  std::string model_file;                 //!< empty = core defaults
  int rays_per_face = 0;                  //!< > 0 overrides the model's
  long long seed = -1;                    //!< >= 0 overrides the model's radiation.seed
  std::function<void(const std::string&)> progress;
};

//! Per-node temperatures of one simulation, in the order of the document's nodes.
struct NodeTemperatures {
  std::vector<std::string> nodes;            //!< document node names
  std::vector<std::string> model_nodes;      //!< the model node each one was simulated as
  std::vector<double> min_K, mean_K, max_K;  //!< over the orbit (steady: all equal) [K]
  //! One standard deviation of each node's temperature from Monte Carlo sampling, worst over
  //! the orbit [K] (SimulationResult::noise_K; 0 where the core gave none).
  std::vector<double> noise_K;
  double orbit_sampling_error_K = 0.0;       //!< transient: estimate of the load sampling's error [K]
  bool transient = false;
  int times = 0;                             //!< number of time points
  int orbits = 0;                            //!< transient: orbits simulated
  double periodicity_residual_K = 0.0;       //!< transient: max |T(P) - T(0)| [K]
  std::string model_description;             //!< one line: where materials/environment came from
  int coldest = 0;                           //!< node with the lowest min_K (index into nodes)
  int hottest = 0;                           //!< node with the highest max_K
  unsigned long long seed = 0;               //!< Monte Carlo seed the simulation used
  int rays_per_face = 0;                     //!< rays per face the simulation used
  std::string sampling;                      //!< noise-targeted sampling's decision, one line
};

//! Simulates the document's mesh as `thermodec simulate` does (the core's
//! simulate_as_front_end: noise-targeted sampling with the core's defaults, then the chain):
//! the same model and seed give the CLI's temperatures bit for bit. With `model_file` empty,
//! the core's bare-mesh defaults apply (load_model of the mesh alone: default coating, orbit
//! environment, steady analysis), stated in model_description. Otherwise the model file gives
//! materials, nodes (capacitance, power, fixed temperature), conductances, environment,
//! analysis and radiation settings. When the document's mesh is the model's own mesh (same
//! faces in the same order, vertices equal to MeshLab's single precision, same nodes), the
//! model is simulated as it is (its exact coordinates and per-face coatings); else the
//! document's mesh replaces the model's, each document node being the model node of the same
//! name, or, when `ids_index_model_nodes` and no name matches, the model node at position
//! node_ids[i] (face quality written by `thermodec convert` is that position), faces taking
//! their node's most common front and back material. `result_file`, if not empty, receives
//! the result JSON (as `thermodec simulate --json`).
//! \throw thermodec::InvalidInput (unreadable/bad model file, a node the model lacks, ...),
//! thermodec::IOError, thermodec::SolverError.
NodeTemperatures simulate_document(const DocumentModelRequest& request, const std::string& result_file = {});

//! Result of reduce_document.
struct DocumentReduction {
  //! The verified reduced mesh; face_node indexes the document's nodes (as the input mesh).
  thermodec::Mesh mesh;
  std::string summary;                 //!< thermodec's summary lines (as `thermodec reduce`)
  std::vector<std::string> warnings;   //!< plots that could not be written
  double max_temperature_difference_K = 0.0;
  double noise_floor_K = 0.0;
  //! merge_nodes: a node of the reduced model made of two or more original nodes.
  struct MergedNode {
    std::string name;                  //!< its name in out_dir/model.json ("wing_py+1")
    std::vector<std::string> members;  //!< the original nodes, in the model's order
    int document_node = -1;            //!< the document node its faces carry (its first member's)
  };
  std::vector<MergedNode> merged;      //!< empty without merge_nodes or when nothing merged
  std::string model_file;              //!< out_dir/model.json: the reduced (merged) model
};

//! `thermodec reduce` on the document: reduce_model with the tolerance [K] and strategy
//! (informed = sensitivity-guided, else uniform), then write_reduction_outputs into `out_dir`
//! (model.json + reduced.obj, report.json, PNG plots when `plots`). `case_files`: further load
//! cases (thermodec::load_case) the reduced model must also meet.
//! \throw thermodec::InvalidInput (tolerance not positive or below twice the noise floor, two
//! document nodes mapped to one model node, a bad case file, ...), IOError, SolverError.
//! merge_nodes: `thermodec reduce --merge-nodes` (reduction/merge_reduction.h); the reduced
//! mesh's faces of a merged node are then labelled with its first member's document node (the
//! merged network and its node map are in out_dir/model.json).
DocumentReduction reduce_document(const DocumentModelRequest& request, double tolerance_K,
                                  bool informed, const std::string& out_dir, bool plots,
                                  const std::vector<std::string>& case_files = {}, bool merge_nodes = false);

//! Result of sensitivity_document, per document node.
struct DocumentSensitivity {
  std::vector<std::string> nodes;
  std::vector<std::vector<double>> ratios, max_abs_dT_K;  //!< per node, increasing ratio
  std::vector<std::vector<int>> faces_after;
  std::vector<int> faces_before;
  std::vector<std::string> files;     //!< written: sensitivity.csv, sensitivity.png
  std::vector<std::string> warnings;  //!< plot failures
};

//! The paper's per-node sensitivity analysis on the document (each node alone decimated by
//! increasing ratios until the whole model's max |dT| over the orbit exceeds 2 x tolerance_K),
//! written as `out_dir`/sensitivity.csv (node, faces_before, ratio, faces_after,
//! max_abs_dT_K) and sensitivity.png.
//! \throw thermodec::InvalidInput, IOError, SolverError.
DocumentSensitivity sensitivity_document(const DocumentModelRequest& request, double tolerance_K,
                                         const std::string& out_dir);

}  // namespace thermodec_meshlab
