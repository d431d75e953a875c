// triangulate_to_vtu MODEL.vtp OUT.vtu [options]
//
// Runs strata::triangulate on an ASCII model (read with the test reader, no VTK) and writes
// the mesh as an ASCII VTK XML UnstructuredGrid: triangles in input coordinates, cell arrays
// RegionId (Int32), MinimumAngle, MaximumAngle, RadiusRatio, Area (Float64), Level (Int32),
// point arrays VertexClass (Int8) and Displacement (Float64, 3 components). Prints the summary
// as JSON on stdout. Options (defaults are the library's):
//   --max-level N --local-max-level N --tolerance X --max-edge-length X --min-edge-length X
//   --thin-layers (ThinLayerRefinement) --no-thin-layer-retry (ThinLayerRetry off)
//   --spring edge|projection --stiffness X --damping X --time-step X --max-iterations N
//   --push all|oneside|closest --push-velocity X --feature-angle DEG --no-flip
//   --no-optimize --passes N --rings N --boundary-tolerance X --minimum-angle DEG
//   --curve-recovery (the default) | --no-curve-recovery | --keep-sharp-corners
//   --boundary OUT.vtp (approximated boundary polylines)
#include "Mesher.h"
#include "VtpAscii.h"

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <fstream>
#include <string>

namespace
{
void usage()
{
  std::fprintf(stderr, "usage: triangulate_to_vtu MODEL.vtp OUT.vtu [options] (see source)\n");
  std::exit(2);
}

void writeVtu(const std::string& path, const strata::MesherResult& r)
{
  std::ofstream f(path);
  if (!f)
  {
    throw std::runtime_error("cannot write " + path);
  }
  char buf[128];
  f << "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" "
       "byte_order=\"LittleEndian\" header_type=\"UInt64\">\n<UnstructuredGrid>\n";
  f << "<Piece NumberOfPoints=\"" << r.points.size() << "\" NumberOfCells=\"" << r.triangles.size()
    << "\">\n";
  f << "<PointData>\n<DataArray type=\"Int8\" Name=\"VertexClass\" format=\"ascii\">\n";
  for (auto c : r.vertexClass)
  {
    f << static_cast<int>(c) << "\n";
  }
  f << "</DataArray>\n<DataArray type=\"Float64\" Name=\"Displacement\" "
       "NumberOfComponents=\"3\" format=\"ascii\">\n";
  for (const auto& d : r.displacement)
  {
    std::snprintf(buf, sizeof(buf), "%.17g %.17g 0\n", d.x, d.y);
    f << buf;
  }
  f << "</DataArray>\n</PointData>\n<CellData>\n";
  auto intArray = [&](const char* name, const strata::LargeVector<int>& v)
  {
    f << "<DataArray type=\"Int32\" Name=\"" << name << "\" format=\"ascii\">\n";
    for (int x : v)
    {
      f << x << "\n";
    }
    f << "</DataArray>\n";
  };
  auto dblArray = [&](const char* name, const strata::LargeVector<double>& v)
  {
    f << "<DataArray type=\"Float64\" Name=\"" << name << "\" format=\"ascii\">\n";
    for (double x : v)
    {
      std::snprintf(buf, sizeof(buf), "%.17g\n", x);
      f << buf;
    }
    f << "</DataArray>\n";
  };
  intArray("RegionId", r.regionId);
  dblArray("MinimumAngle", r.minAngle);
  dblArray("MaximumAngle", r.maxAngle);
  dblArray("RadiusRatio", r.radiusRatio);
  dblArray("Area", r.area);
  intArray("Level", r.level);
  f << "</CellData>\n<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" "
       "format=\"ascii\">\n";
  for (const auto& p : r.points)
  {
    std::snprintf(buf, sizeof(buf), "%.17g %.17g 0\n", p.x + r.origin.x, p.y + r.origin.y);
    f << buf;
  }
  f << "</DataArray>\n</Points>\n<Cells>\n<DataArray type=\"Int64\" Name=\"connectivity\" "
       "format=\"ascii\">\n";
  for (const auto& t : r.triangles)
  {
    f << t[0] << " " << t[1] << " " << t[2] << "\n";
  }
  f << "</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
  for (std::size_t i = 0; i < r.triangles.size(); ++i)
  {
    f << 3 * (i + 1) << "\n";
  }
  f << "</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
  for (std::size_t i = 0; i < r.triangles.size(); ++i)
  {
    f << "5\n";
  }
  f << "</DataArray>\n</Cells>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";
}

void writeBoundaryVtp(const std::string& path, const strata::MesherResult& r)
{
  std::ofstream f(path);
  char buf[128];
  std::size_t np = 0;
  for (const auto& c : r.boundary)
  {
    np += c.points.size();
  }
  f << "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\" version=\"1.0\" "
       "byte_order=\"LittleEndian\" header_type=\"UInt64\">\n<PolyData>\n";
  f << "<Piece NumberOfPoints=\"" << np << "\" NumberOfLines=\"" << r.boundary.size()
    << "\">\n<CellData>\n<DataArray type=\"Int32\" Name=\"LeftRegion\" format=\"ascii\">\n";
  for (const auto& c : r.boundary)
  {
    f << c.left << "\n";
  }
  f << "</DataArray>\n<DataArray type=\"Int32\" Name=\"RightRegion\" format=\"ascii\">\n";
  for (const auto& c : r.boundary)
  {
    f << c.right << "\n";
  }
  f << "</DataArray>\n</CellData>\n<Points>\n<DataArray type=\"Float64\" "
       "NumberOfComponents=\"3\" format=\"ascii\">\n";
  for (const auto& c : r.boundary)
  {
    for (const auto& p : c.points)
    {
      std::snprintf(buf, sizeof(buf), "%.17g %.17g 0\n", p.x + r.origin.x, p.y + r.origin.y);
      f << buf;
    }
  }
  f << "</DataArray>\n</Points>\n<Lines>\n<DataArray type=\"Int64\" Name=\"connectivity\" "
       "format=\"ascii\">\n";
  for (std::size_t i = 0; i < np; ++i)
  {
    f << i << "\n";
  }
  f << "</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
  std::size_t off = 0;
  for (const auto& c : r.boundary)
  {
    off += c.points.size();
    f << off << "\n";
  }
  f << "</DataArray>\n</Lines>\n</Piece>\n</PolyData>\n</VTKFile>\n";
}
} // namespace

int main(int argc, char** argv)
{
  if (argc < 3)
  {
    usage();
  }
  strata::MesherParams p;
  std::string boundaryPath;
  for (int i = 3; i < argc; ++i)
  {
    const std::string a = argv[i];
    auto next = [&]() -> const char*
    {
      if (i + 1 >= argc)
      {
        usage();
      }
      return argv[++i];
    };
    if (a == "--max-level")
      p.grid.maxLevel = std::atoi(next());
    else if (a == "--local-max-level")
      p.grid.localMaxLevel = std::atoi(next());
    else if (a == "--tolerance")
      p.grid.tolerance = std::atof(next());
    else if (a == "--thin-layers")
      p.grid.thinLayerRefinement = true;
    else if (a == "--no-thin-layer-retry")
      p.thinLayerRetry = false;
    else if (a == "--max-edge-length")
      p.grid.maxEdgeLength = std::atof(next());
    else if (a == "--min-edge-length")
      p.grid.minEdgeLength = std::atof(next());
    else if (a == "--spring")
      p.compression.springConfiguration = std::strcmp(next(), "edge") == 0
        ? strata::SpringConfiguration::EdgeOnly
        : strata::SpringConfiguration::EdgeAndProjection;
    else if (a == "--stiffness")
      p.compression.springStiffness = std::atof(next());
    else if (a == "--damping")
      p.compression.damping = std::atof(next());
    else if (a == "--time-step")
      p.compression.timeStep = std::atof(next());
    else if (a == "--max-iterations")
      p.compression.maxIterations = std::atoi(next());
    else if (a == "--push")
    {
      const std::string v = next();
      p.compression.pushCriterion = v == "all" ? strata::PushCriterion::AllCandidates
        : v == "closest"                       ? strata::PushCriterion::Closest
                                               : strata::PushCriterion::OneSide;
    }
    else if (a == "--push-velocity")
      p.compression.pushVelocity = std::atof(next());
    else if (a == "--feature-angle")
      p.compression.featureAngle = std::atof(next());
    else if (a == "--no-flip")
      p.compression.flipDegenerate = false;
    else if (a == "--no-optimize")
      p.compression.optimize = false;
    else if (a == "--passes")
      p.compression.optimizationPasses = std::atoi(next());
    else if (a == "--boundary-tolerance")
      p.compression.boundaryTolerance = std::atof(next());
    else if (a == "--curve-recovery")
      p.curveRecovery = true;
    else if (a == "--no-curve-recovery")
      p.curveRecovery = false;
    else if (a == "--keep-sharp-corners")
      p.keepSharpCorners = true;
    else if (a == "--minimum-angle")
      p.refinement.minimumAngle = std::atof(next());
    else if (a == "--rings")
      p.compression.activeRings = std::atoi(next());
    else if (a == "--boundary")
      boundaryPath = next();
    else
      usage();
  }
  try
  {
    const strata::RawPolylines raw = strata_test::readVtpAscii(argv[1]);
    const strata::MesherResult r = strata::triangulate(raw, p);
    writeVtu(argv[2], r);
    if (!boundaryPath.empty())
    {
      writeBoundaryVtp(boundaryPath, r);
    }
    const auto& s = r.summary;
    std::printf("{\n \"triangles\": %zu, \"vertices\": %zu,\n \"min_angle\": %.4f, "
                "\"max_angle\": %.4f,\n \"pct_angles_30_60\": %.2f, \"pct_tris_30_60\": %.2f,\n"
                " \"max_boundary_deviation\": %.6g, \"max_relative_deviation\": %.4g,\n"
                " \"relative_deviation_edge\": %.4g,\n"
                " \"max_boundary_vertex_distance\": %.3g,\n"
                " \"max_region_area_error_pct\": %.4f, \"max_region_misplaced_area_pct\": %.4f,\n"
                " \"finest_edge_length\": %.6g,\n"
                " \"iterations\": %d, \"seconds\": %.4f,\n"
                " \"boundary_splits\": %zu, \"triangles_at_sharp_corners\": %zu,\n"
                " \"triangles_below_minimum_angle\": %zu,\n"
                " \"refinement_vertices\": %zu, \"curve_vertices\": %zu,\n"
                " \"sharp_corners\": %zu, \"kept_corners\": %zu, \"kept_corner_triangles\": %zu,\n"
                " \"thin_layer_mesh\": %s, \"local_max_level\": %d,\n",
      s.triangles,
      s.vertices,
      s.minAngle,
      s.maxAngle,
      s.percentAngles30to60,
      s.percentTriangles30to60,
      s.maxBoundaryDeviation,
      s.maxRelativeDeviation,
      s.relativeDeviationEdge,
      s.maxBoundaryVertexDistance,
      100.0 * s.maxRegionAreaError,
      100.0 * s.maxRegionMisplacedArea,
      s.finestEdgeLength,
      s.iterations,
      s.totalSeconds,
      s.boundarySplits,
      s.trianglesAtSharpCorners,
      s.trianglesBelowMinimumAngle,
      s.refinementVertices,
      s.curveVertices,
      s.sharpCorners,
      r.keptCorners.size(),
      s.keptCornerTriangles,
      s.thinLayerMesh ? "true" : "false",
      s.localMaxLevel);
    std::printf(" \"kept_corner_list\": [");
    for (std::size_t i = 0; i < r.keptCorners.size(); ++i)
    {
      const auto& k = r.keptCorners[i];
      std::printf("%s{\"x\": %.17g, \"y\": %.17g, \"region\": %d, \"angle\": %.4f, "
                  "\"radius\": %.17g, \"outline\": [",
        i ? ", " : "",
        k.apex.x + r.origin.x,
        k.apex.y + r.origin.y,
        k.region,
        k.angle,
        k.radius);
      for (std::size_t j = 0; j < k.outline.size(); ++j)
      {
        std::printf("%s[%.17g, %.17g]",
          j ? ", " : "",
          k.outline[j].x + r.origin.x,
          k.outline[j].y + r.origin.y);
      }
      std::printf("]}");
    }
    std::printf("],\n");
    std::printf(" \"stages\": {");
    for (std::size_t i = 0; i < s.secondsPerStage.size(); ++i)
    {
      std::printf("%s\"%s\": %.4f",
        i ? ", " : "",
        s.secondsPerStage[i].first.c_str(),
        s.secondsPerStage[i].second);
    }
    std::printf("},\n \"warnings\": [");
    for (std::size_t i = 0; i < r.warnings.size(); ++i)
    {
      std::printf("%s\"%s\"", i ? ", " : "", r.warnings[i].c_str());
    }
    std::printf("]\n}\n");
  }
  catch (const std::exception& e)
  {
    std::fprintf(stderr, "triangulate_to_vtu: %s\n", e.what());
    return 1;
  }
  return 0;
}
