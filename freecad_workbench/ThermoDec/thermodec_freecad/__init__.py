"""ThermoDec workbench: thermal nodes and coatings on CAD, dense tagged tessellation, export to
thermodec's model format and runs of the thermodec core through its Python module."""
