/**
 * @class   vtkStrataMeshInput
 * @brief   converts a vtkPolyData polyline model into the core's raw input (not wrapped)
 *
 * Shared by the StrataMesh filters: fetches the point coordinates, the cells as
 * offsets/connectivity and the region label arrays of either input form (Loops: `RegionId`;
 * Shared curves: `LeftRegion`/`RightRegion`), and hands them to strata::buildModel. Array
 * names are user-selectable; an empty name means "the default name", and Form `Auto` picks
 * Shared curves when both label arrays are present, else Loops.
 *
 * @sa vtkPolylineSignedDistanceFilter vtkPolylineSignedDistance
 */
#ifndef vtkStrataMeshInput_h
#define vtkStrataMeshInput_h

#include "Model.h" // strata::Model, strata::RawPolylines

#include <vtkIndent.h> // vtkIndent, ostream

#include <string>

class vtkPolyData;

class vtkStrataMeshInput
{
public:
  /// Input form of a model, as exposed by the filters' `Form` property.
  enum Forms
  {
    FORM_AUTO = 0,
    FORM_LOOPS = 1,
    FORM_SHARED_CURVES = 2
  };

  /// Names of the label arrays and the form to read.
  struct Selection
  {
    int Form = FORM_AUTO;
    std::string RegionArray = "RegionId";
    std::string LeftRegionArray = "LeftRegion";
    std::string RightRegionArray = "RightRegion";
  };

  /// A selection from a filter's properties; null or empty names mean the default names.
  static Selection MakeSelection(
    int form, const char* regionArray, const char* leftRegionArray, const char* rightRegionArray);

  /// Converts the polydata (lines, then polygons, then other cells) into raw core input.
  /// Throws strata::InputError naming the array at fault (missing, wrong size, not integral).
  static strata::RawPolylines ToRaw(vtkPolyData* input, const Selection& selection);

  /// ToRaw followed by strata::buildModel.
  static strata::Model BuildModel(vtkPolyData* input, const Selection& selection);

  /// Prints a filter's model-reading properties (Form and the three array names, "(none)"
  /// for a null name), as its PrintSelf does.
  static void PrintSelection(ostream& os,
    vtkIndent indent,
    int form,
    const char* regionArray,
    const char* leftRegionArray,
    const char* rightRegionArray);
};

#endif
