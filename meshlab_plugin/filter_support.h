#pragma once
//! What every Thermal filter shares besides the document mesh: the model-file parameter (a file
//! widget, found beside the mesh or remembered), parameters that scripts may give as strings or
//! files, and long core calls run off the main thread with progress reported from it.
#include <common/interfaces.h>

#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace thermodec_meshlab {

//! Adds "model_file": a file widget (RichOpenFile, *.json) whose default is the model file
//! choose_model_file would take for `layer` (so the dialog shows it).
void add_model_file_parameter(RichParameterList& params, MeshModel& layer, const QString& help);

//! The value of a text parameter whether a script gives it as RichString, RichOpenFile or
//! RichSaveFile (shipped scripts from earlier versions give "model_file" as a string); trimmed.
QString text_parameter(const RichParameterList& params, const QString& name);

//! The model file a filter uses, and how it was chosen (for the log).
struct ModelFileChoice {
  QString path;  //!< empty: none, the core's bare-mesh defaults
  QString how;   //!< "given", "found beside the mesh", "used last with this layer", ...
};

//! The parameter if set; else the model file last used with `layer` (or the layer it was made
//! from); else a model JSON beside the layer's file whose "mesh" has the layer file's stem
//! (sample_models/satellite/model.json names satellite.obj: found for satellite.ply); else the
//! one last used since MeshLab started. The choice is remembered on the layer and until
//! MeshLab quits.
ModelFileChoice choose_model_file(const RichParameterList& params, MeshModel& layer);

//! Maps a progress message to the percentage its stage starts at, or < 0 for a message that
//! starts no stage.
using StageOf = std::function<double(const std::string&)>;

//! A StageOf from an ordered table (text, percent): a message starts the first stage after the
//! current one whose text it contains (the same text may come back later in the table, e.g.
//! the two simulations of noise-targeted sampling).
StageOf ordered_stages(std::vector<std::pair<std::string, double>> table);

//! The stages of one front-end simulation (thermal/simulate_model.h: simulate_as_front_end),
//! twice with noise-targeted sampling (an estimate, then the simulation); used by simulate and
//! by export, which simulates before it writes.
StageOf simulation_chain_stages();

//! Runs `work` on a worker thread while the calling (main) thread waits, forwarding its
//! progress messages: each goes to `log` and to MeshLab's callback `cb` (which repaints the
//! GUI) from the main thread only, every 100 ms, as the percentage of the stage `stage_of`
//! gives (creeping on slowly while a stage lasts). Exceptions of `work` are rethrown here.
//! MeshLab 2020.09's callback never asks to stop, so there is no cancel.
void run_with_progress(vcg::CallBackPos* cb, const StageOf& stage_of,
                       const std::function<void(const std::function<void(const std::string&)>&)>& work,
                       const std::function<void(const std::string&)>& log);

//! `text` with <, > and & escaped for MeshLab's HTML help texts and tooltips.
QString html_escaped(const QString& text);

}  // namespace thermodec_meshlab
