#pragma once
//! The exchange export (core exchange/export_model.h) of a MeshLab document, behind an
//! interface the C++14 plugin sources can include (see core_calls.h). Compiled as C++17.
#include <string>
#include <vector>

#include "core_calls.h"

namespace thermodec_meshlab {

//! What the "Thermal: export for other tools" filter asks of the core.
struct DocumentExport {
  std::string format;           //!< a name of export_format_rows()
  std::string out;              //!< file (nastran, esatan, sinda), folder (vtk) or prefix (csv)
  std::string stem;             //!< names the VTK series (<stem>.pvd, <stem>_0000.vtu, ...)
  double noise_target_K = 0.0;  //!< noise-targeted sampling as `thermodec export` (0 = off)
};

//! A row of the core's table of export formats (exchange/export_formats.h), in plain types.
struct ExportFormatRow {
  std::string name;       //!< the `thermodec export --format` value
  std::string title;      //!< "ESATAN-TMS network"
  std::string help;       //!< one paragraph
  bool needs_simulation;  //!< false: written from the model alone
};

//! The core's export formats in menu order.
std::vector<ExportFormatRow> export_format_rows();

//! The default output of `format` for a model at `base` (a path without extension): the file
//! `base` + the format's extension, the folder `base_<name>`, or the prefix `base`.
//! \throw thermodec::InvalidInput for an unknown format.
std::string default_export_path(const std::string& format, const std::string& base);

//! Exports the document's thermal model (built as simulate_document builds it; the model file,
//! when given, is protected from being overwritten) exactly as `thermodec export` exports a
//! model: the NASTRAN mesh as is, the network and result formats after the same simulation.
//! Returns the files written.
//! \throw thermodec::InvalidInput (unknown format, an output onto the model file or of the
//! wrong kind, as document_model), thermodec::IOError, thermodec::SolverError.
std::vector<std::string> export_document(const DocumentModelRequest& request, const DocumentExport& what);

}  // namespace thermodec_meshlab
