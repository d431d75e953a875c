// Test-only reader of the ASCII VTK XML PolyData files in Data/ into the core's RawPolylines,
// so that the core tests and benchmarks run without VTK. It understands exactly what the
// files in Data/ use: inline ascii Points, Lines/Polys offsets and connectivity, Int32 cell
// arrays. Anything else makes it throw std::runtime_error.
#ifndef StrataMesh_VtpAscii_h
#define StrataMesh_VtpAscii_h

#include "Model.h"

#include <string>

namespace strata_test
{

/// Full path of a file under Data/ (e.g. "lake_superior.vtp", "bad_inputs/empty.vtp").
std::string dataPath(const std::string& name);

/// Reads a .vtp file. Lines become CellKind::Line cells, then Polys become CellKind::Polygon
/// cells. Cell arrays RegionId / LeftRegion / RightRegion fill the matching fields (form Auto).
strata::RawPolylines readVtpAscii(const std::string& path);

} // namespace strata_test

#endif
