#include "vtkStrataMeshInput.h"

#include "Errors.h"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>

#include <cmath>

namespace
{

vtkDataArray* FindLabels(vtkPolyData* input, const std::string& name)
{
  return name.empty() ? nullptr : input->GetCellData()->GetArray(name.c_str());
}

std::vector<int> ToLabels(vtkDataArray* array, vtkIdType numberOfCells)
{
  if (array->GetNumberOfComponents() != 1)
  {
    throw strata::InputError(std::string("region array '") + array->GetName() + "' has " +
      std::to_string(array->GetNumberOfComponents()) + " components; it needs 1");
  }
  if (array->GetNumberOfTuples() != numberOfCells)
  {
    throw strata::InputError(std::string("region array '") + array->GetName() + "' has " +
      std::to_string(array->GetNumberOfTuples()) + " values for " +
      std::to_string(numberOfCells) + " cells");
  }
  std::vector<int> labels(static_cast<std::size_t>(numberOfCells));
  for (vtkIdType c = 0; c < numberOfCells; ++c)
  {
    const double v = array->GetComponent(c, 0);
    if (!std::isfinite(v) || v != std::floor(v) || std::fabs(v) > 1e9)
    {
      throw strata::InputError(std::string("region array '") + array->GetName() + "' value " +
        std::to_string(v) + " of cell " + std::to_string(c) + " is not an integer region id");
    }
    labels[static_cast<std::size_t>(c)] = static_cast<int>(v);
  }
  return labels;
}

// The names of the input's cell arrays, for the messages.
std::string CellArrayNames(vtkPolyData* input)
{
  vtkCellData* data = input->GetCellData();
  std::string names;
  for (int i = 0; i < data->GetNumberOfArrays(); ++i)
  {
    const char* name = data->GetArrayName(i);
    names += (names.empty() ? "'" : ", '") + std::string(name ? name : "") + "'";
  }
  return names.empty() ? "none" : names;
}

void AppendCells(vtkCellArray* cells, strata::CellKind kind, strata::RawPolylines& raw)
{
  if (!cells)
  {
    return;
  }
  const vtkIdType n = cells->GetNumberOfCells();
  vtkIdType npts = 0;
  const vtkIdType* pts = nullptr;
  for (vtkIdType c = 0; c < n; ++c)
  {
    cells->GetCellAtId(c, npts, pts);
    raw.connectivity.insert(raw.connectivity.end(), pts, pts + npts);
    raw.offsets.push_back(static_cast<std::int64_t>(raw.connectivity.size()));
    raw.kinds.push_back(kind);
  }
}

} // namespace

vtkStrataMeshInput::Selection vtkStrataMeshInput::MakeSelection(
  int form, const char* regionArray, const char* leftRegionArray, const char* rightRegionArray)
{
  Selection selection;
  selection.Form = form;
  if (regionArray && *regionArray)
  {
    selection.RegionArray = regionArray;
  }
  if (leftRegionArray && *leftRegionArray)
  {
    selection.LeftRegionArray = leftRegionArray;
  }
  if (rightRegionArray && *rightRegionArray)
  {
    selection.RightRegionArray = rightRegionArray;
  }
  return selection;
}

strata::RawPolylines vtkStrataMeshInput::ToRaw(vtkPolyData* input, const Selection& selection)
{
  strata::RawPolylines raw;
  raw.offsets.push_back(0);
  if (!input)
  {
    return raw;
  }
  const vtkIdType numberOfPoints = input->GetNumberOfPoints();
  raw.points.resize(static_cast<std::size_t>(numberOfPoints));
  double zFirst = 0.0;
  vtkIdType offPlane = -1; // the first point whose z differs from the first point's
  for (vtkIdType i = 0; i < numberOfPoints; ++i)
  {
    double p[3];
    input->GetPoint(i, p);
    raw.points[static_cast<std::size_t>(i)] = { p[0], p[1] };
    zFirst = i == 0 ? p[2] : zFirst;
    offPlane = offPlane < 0 && p[2] != zFirst ? i : offPlane;
  }
  // The model is the points' (x, y): a z is dropped, with a warning.
  if (offPlane >= 0)
  {
    double p[3];
    input->GetPoint(offPlane, p);
    raw.notes.push_back("the input's points are not in one plane z = constant (point 0 has z = " +
      std::to_string(zFirst) + ", point " + std::to_string(offPlane) +
      " z = " + std::to_string(p[2]) + "): the model is their projection on z = 0");
  }
  else if (numberOfPoints > 0 && zFirst != 0.0)
  {
    raw.notes.push_back("the input lies in the plane z = " + std::to_string(zFirst) +
      "; the mesh is made in the plane z = 0");
  }
  // vtkPolyData orders its cells verts, lines, polys, strips: keep that numbering so that the
  // cell ids in messages are the ones ParaView's spreadsheet shows.
  AppendCells(input->GetVerts(), strata::CellKind::Other, raw);
  AppendCells(input->GetLines(), strata::CellKind::Line, raw);
  AppendCells(input->GetPolys(), strata::CellKind::Polygon, raw);
  AppendCells(input->GetStrips(), strata::CellKind::Other, raw);

  const vtkIdType numberOfCells = input->GetNumberOfCells();
  vtkDataArray* region = FindLabels(input, selection.RegionArray);
  vtkDataArray* left = FindLabels(input, selection.LeftRegionArray);
  vtkDataArray* right = FindLabels(input, selection.RightRegionArray);
  const bool shared = left && right && left != right;
  const std::string arrays = "; the input's cell arrays: " + CellArrayNames(input);
  const std::string sameNames = selection.LeftRegionArray == selection.RightRegionArray
    ? " (LeftRegionArrayName and RightRegionArrayName are both '" + selection.LeftRegionArray +
      "': the two arrays hold each curve's left and right region)"
    : "";
  switch (selection.Form)
  {
    case FORM_LOOPS:
      raw.form = strata::ModelForm::Loops;
      if (!region && numberOfCells > 0)
      {
        throw strata::InputError(
          "Loops form: no cell array named '" + selection.RegionArray + "'" + arrays);
      }
      break;
    case FORM_SHARED_CURVES:
      raw.form = strata::ModelForm::SharedCurves;
      if (!shared && numberOfCells > 0)
      {
        throw strata::InputError("Shared curves form: needs two cell arrays, '" +
          selection.LeftRegionArray + "' and '" + selection.RightRegionArray + "'" + sameNames +
          arrays);
      }
      break;
    default:
      raw.form = strata::ModelForm::Auto;
      if (!shared && !region && numberOfCells > 0)
      {
        throw strata::InputError("no region arrays: Form = Auto looks for a cell array named '" +
          selection.RegionArray + "' (Loops form) or two named '" + selection.LeftRegionArray +
          "' and '" + selection.RightRegionArray + "' (Shared curves form)" + sameNames + arrays);
      }
      if (!shared && input->GetCellData()->GetNumberOfArrays() > 1)
      {
        // The array drop-downs take the input's first array when it has none of the default
        // names, so that a Shared curves model with other names reads as Loops.
        raw.formNote = "Form = Auto read it as the Loops form with the cell array '" +
          selection.RegionArray + "'" + sameNames +
          "; for the Shared curves form choose LeftRegionArrayName and RightRegionArrayName" +
          arrays;
      }
      break;
  }
  if (shared && raw.form != strata::ModelForm::Loops)
  {
    raw.leftRegion = ToLabels(left, numberOfCells);
    raw.rightRegion = ToLabels(right, numberOfCells);
  }
  else if (region && raw.form != strata::ModelForm::SharedCurves)
  {
    raw.regionId = ToLabels(region, numberOfCells);
  }
  return raw;
}

strata::Model vtkStrataMeshInput::BuildModel(vtkPolyData* input, const Selection& selection)
{
  return strata::buildModel(ToRaw(input, selection));
}

void vtkStrataMeshInput::PrintSelection(ostream& os,
  vtkIndent indent,
  int form,
  const char* regionArray,
  const char* leftRegionArray,
  const char* rightRegionArray)
{
  static const char* const forms[] = { " (Auto)", " (Loops)", " (Shared curves)" };
  os << indent << "Form: " << form << (form >= 0 && form <= 2 ? forms[form] : "") << "\n";
  os << indent << "RegionArrayName: " << (regionArray ? regionArray : "(none)") << "\n";
  os << indent << "LeftRegionArrayName: " << (leftRegionArray ? leftRegionArray : "(none)") << "\n";
  os << indent << "RightRegionArrayName: " << (rightRegionArray ? rightRegionArray : "(none)")
     << "\n";
}
