/**
 * @class   vtkStrataMeshRange
 * @brief   checks a filter property against its documented range (not wrapped)
 *
 * The StrataMesh filters keep the values their setters receive (no silent clamping) and
 * check them when they execute: a value out of range fails the request with an error that
 * names the property, its value and the range, e.g.
 * `MaxLevel = 99 is out of range [-1, 60]`. Ranges are written as in the documentation:
 * `[` and `]` closed, `(` and `)` open, `inf` unbounded; NaN is never in range.
 *
 * @sa vtkStrataMeshAlgorithm vtkPolylineSignedDistanceFilter vtkPolylineSignedDistance
 */
#ifndef vtkStrataMeshRange_h
#define vtkStrataMeshRange_h

#include <string>

class vtkObject;

class vtkStrataMeshRange
{
public:
  /// Bounds of a range: closed (the bound is allowed) or open.
  enum Bound
  {
    CLOSED = 0,
    OPEN = 1
  };

  /// "<name> = <value> is out of range [<min>, <max>]", or "" when min <= value <= max.
  static std::string Message(const char* name, int value, int min, int max);

  /// The same for doubles, with open or closed bounds; max may be +inf. NaN is out of range.
  static std::string Message(const char* name,
    double value,
    double min,
    double max,
    Bound minBound = CLOSED,
    Bound maxBound = CLOSED);

  ///@{
  /**
   * Whether the value is in range; if not, reports Message() as an error of `self`
   * (vtkErrorWithObjectMacro: printed, or an ErrorEvent for observers) and returns false.
   */
  static bool Check(vtkObject* self, const char* name, int value, int min, int max);
  static bool Check(vtkObject* self,
    const char* name,
    double value,
    double min,
    double max,
    Bound minBound = CLOSED,
    Bound maxBound = CLOSED);
  ///@}

  /// Reports `message` (when not empty) as an error of `self`; returns whether it was empty.
  static bool Report(vtkObject* self, const std::string& message);
};

#endif
