// Helpers shared by the adapter tests (test-only, header-only): the data-file reader, the
// error/warning observer and the signed area of a triangle cell.
#ifndef StrataMesh_AdapterTestUtilities_h
#define StrataMesh_AdapterTestUtilities_h

#include <vtkCommand.h>
#include <vtkObject.h>
#include <vtkSmartPointer.h>
#include <vtkType.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLPolyDataReader.h>

#include <string>

namespace strata_test
{

/// The path of a file of Data/ (STRATAMESH_DATA_DIR is defined by AdapterTests.cmake).
inline std::string DataFile(const std::string& name)
{
  return std::string(STRATAMESH_DATA_DIR) + "/" + name;
}

/// A reader of a .vtp file of Data/.
inline vtkSmartPointer<vtkXMLPolyDataReader> Reader(const std::string& name)
{
  auto reader = vtkSmartPointer<vtkXMLPolyDataReader>::New();
  reader->SetFileName(DataFile(name).c_str());
  return reader;
}

/// Records the error and warning messages an object emits (observed messages are not printed).
class MessageLog : public vtkCommand
{
public:
  static MessageLog* New() { return new MessageLog; }
  void Execute(vtkObject*, unsigned long event, void* data) override
  {
    (event == vtkCommand::ErrorEvent ? this->Errors : this->Warnings) +=
      static_cast<const char*>(data);
  }
  /// Whether an error contains `message`.
  bool Has(const std::string& message) const
  {
    return this->Errors.find(message) != std::string::npos;
  }
  std::string Errors, Warnings;
};

/// Observes the errors and warnings of `object`; the observer lives as long as the object.
inline vtkSmartPointer<MessageLog> Watch(vtkObject* object)
{
  auto log = vtkSmartPointer<MessageLog>::New();
  object->AddObserver(vtkCommand::ErrorEvent, log);
  object->AddObserver(vtkCommand::WarningEvent, log);
  return log;
}

/// The signed area of triangle `cell` of `grid` in the xy plane (> 0: counter-clockwise).
inline double SignedArea(vtkUnstructuredGrid* grid, vtkIdType cell)
{
  vtkIdType npts = 0;
  const vtkIdType* ids = nullptr;
  grid->GetCellPoints(cell, npts, ids);
  double a[3], b[3], c[3];
  grid->GetPoint(ids[0], a);
  grid->GetPoint(ids[1], b);
  grid->GetPoint(ids[2], c);
  return 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]));
}

} // namespace strata_test

#endif
