#include "vtkStrataMeshRange.h"

#include <vtkObject.h>
#include <vtkSetGet.h>

#include <cmath>
#include <sstream>

namespace
{

void Write(std::ostringstream& os, double value)
{
  if (std::isinf(value))
  {
    os << (value > 0 ? "inf" : "-inf");
  }
  else
  {
    os << value;
  }
}

} // namespace

std::string vtkStrataMeshRange::Message(const char* name, int value, int min, int max)
{
  if (value >= min && value <= max)
  {
    return std::string();
  }
  std::ostringstream os;
  os << name << " = " << value << " is out of range [" << min << ", " << max << "]";
  return os.str();
}

std::string vtkStrataMeshRange::Message(const char* name,
  double value,
  double min,
  double max,
  Bound minBound,
  Bound maxBound)
{
  const bool aboveMin = minBound == OPEN ? value > min : value >= min;
  const bool belowMax = maxBound == OPEN || std::isinf(max) ? value < max : value <= max;
  if (aboveMin && belowMax)
  {
    return std::string();
  }
  std::ostringstream os;
  os << name << " = ";
  Write(os, value);
  os << " is out of range " << (minBound == OPEN ? "(" : "[");
  Write(os, min);
  os << ", ";
  Write(os, max);
  os << (maxBound == OPEN || std::isinf(max) ? ")" : "]");
  return os.str();
}

bool vtkStrataMeshRange::Report(vtkObject* self, const std::string& message)
{
  if (message.empty())
  {
    return true;
  }
  vtkErrorWithObjectMacro(self, << message);
  return false;
}

bool vtkStrataMeshRange::Check(vtkObject* self, const char* name, int value, int min, int max)
{
  return Report(self, Message(name, value, min, max));
}

bool vtkStrataMeshRange::Check(vtkObject* self,
  const char* name,
  double value,
  double min,
  double max,
  Bound minBound,
  Bound maxBound)
{
  return Report(self, Message(name, value, min, max, minBound, maxBound));
}
