#include "VtpAscii.h"

#include <algorithm>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>

#ifndef STRATAMESH_DATA_DIR
#error "STRATAMESH_DATA_DIR must be defined by the build"
#endif

namespace strata_test
{
namespace
{

// Returns the text between the opening tag that contains `marker` (searched from `from`) and
// the next "</DataArray>", or an empty string when the marker is absent before `limit`.
std::string arrayText(const std::string& xml, const std::string& marker, std::size_t from,
  std::size_t limit)
{
  const std::size_t m = xml.find(marker, from);
  if (m == std::string::npos || m >= limit)
  {
    return {};
  }
  const std::size_t open = xml.find('>', m);
  // The values end at the first child element (<InformationKey>) or at </DataArray>.
  const std::size_t close =
    std::min(xml.find("</DataArray>", open), open == std::string::npos ? open : xml.find('<', open));
  if (open == std::string::npos || close == std::string::npos)
  {
    throw std::runtime_error("malformed DataArray " + marker);
  }
  if (xml.substr(m, open - m).find("format=\"ascii\"") == std::string::npos)
  {
    throw std::runtime_error("only ascii DataArrays are supported: " + marker);
  }
  return xml.substr(open + 1, close - open - 1);
}

template <typename T>
std::vector<T> numbers(const std::string& text)
{
  std::vector<T> out;
  std::istringstream in(text);
  std::string token;
  while (in >> token)
  {
    if (token == "nan" || token == "NaN" || token == "-nan")
    {
      out.push_back(static_cast<T>(std::numeric_limits<double>::quiet_NaN()));
    }
    else
    {
      out.push_back(static_cast<T>(std::stod(token)));
    }
  }
  return out;
}

std::pair<std::size_t, std::size_t> section(const std::string& xml, const std::string& tag)
{
  const std::size_t b = xml.find("<" + tag + ">");
  if (b == std::string::npos)
  {
    return { std::string::npos, std::string::npos };
  }
  return { b, xml.find("</" + tag + ">", b) };
}

} // namespace

std::string dataPath(const std::string& name)
{
  return std::string(STRATAMESH_DATA_DIR) + "/" + name;
}

strata::RawPolylines readVtpAscii(const std::string& path)
{
  std::ifstream f(path);
  if (!f)
  {
    throw std::runtime_error("cannot open " + path);
  }
  std::stringstream ss;
  ss << f.rdbuf();
  const std::string xml = ss.str();

  strata::RawPolylines raw;
  const auto points = section(xml, "Points");
  if (points.first != std::string::npos)
  {
    const auto xyz = numbers<double>(arrayText(xml, "Name=\"Points\"", points.first, points.second));
    for (std::size_t i = 0; i + 2 < xyz.size(); i += 3)
    {
      raw.points.push_back({ xyz[i], xyz[i + 1] });
    }
  }
  raw.offsets.push_back(0);
  for (const char* tag : { "Lines", "Polys" })
  {
    const auto s = section(xml, tag);
    if (s.first == std::string::npos)
    {
      continue;
    }
    const auto conn =
      numbers<std::int64_t>(arrayText(xml, "Name=\"connectivity\"", s.first, s.second));
    const auto offs = numbers<std::int64_t>(arrayText(xml, "Name=\"offsets\"", s.first, s.second));
    const std::int64_t base = static_cast<std::int64_t>(raw.connectivity.size());
    raw.connectivity.insert(raw.connectivity.end(), conn.begin(), conn.end());
    for (std::int64_t o : offs)
    {
      raw.offsets.push_back(base + o);
      raw.kinds.push_back(tag[0] == 'L' ? strata::CellKind::Line : strata::CellKind::Polygon);
    }
  }
  const auto cells = section(xml, "CellData");
  if (cells.first != std::string::npos)
  {
    raw.regionId = numbers<int>(arrayText(xml, "Name=\"RegionId\"", cells.first, cells.second));
    raw.leftRegion = numbers<int>(arrayText(xml, "Name=\"LeftRegion\"", cells.first, cells.second));
    raw.rightRegion =
      numbers<int>(arrayText(xml, "Name=\"RightRegion\"", cells.first, cells.second));
  }
  return raw;
}

} // namespace strata_test
