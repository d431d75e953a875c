// stratamesh_consumer <model.vtp> [<mesh.vtu>]: meshes a StrataMesh polyline model with
// vtkPhysicalCompressionTriangulator and writes the triangles as a binary .vtu (which
// Debian's ParaView can read back). Exit code 0 when the mesh has triangles and the cell
// array RegionId; 1 otherwise (errors on stderr).
#include <vtkCellData.h>
#include <vtkCommand.h>
#include <vtkNew.h>
#include <vtkPhysicalCompressionTriangulator.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLPolyDataReader.h>
#include <vtkXMLUnstructuredGridReader.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include <iostream>
#include <string>

namespace
{

// Counts the errors an algorithm reports (VTK prints them; Update() does not return them).
class ErrorCounter : public vtkCommand
{
public:
  static ErrorCounter* New() { return new ErrorCounter; }
  void Execute(vtkObject*, unsigned long, void*) override { ++this->Count; }
  int Count = 0;
};

bool CheckMesh(vtkUnstructuredGrid* mesh, const std::string& what)
{
  if (!mesh || mesh->GetNumberOfCells() == 0)
  {
    std::cerr << what << ": no triangles\n";
    return false;
  }
  if (!mesh->GetCellData()->GetArray("RegionId"))
  {
    std::cerr << what << ": no RegionId cell array\n";
    return false;
  }
  return true;
}

} // namespace

int main(int argc, char* argv[])
{
  if (argc < 2 || argc > 3)
  {
    std::cerr << "usage: " << argv[0] << " <model.vtp> [<mesh.vtu>]\n";
    return 1;
  }
  const std::string input = argv[1];
  std::string output = argc > 2 ? argv[2] : "";
  if (output.empty())
  {
    const std::string::size_type dot = input.rfind('.');
    const std::string::size_type slash = input.find_last_of('/');
    const bool hasExtension =
      dot != std::string::npos && (slash == std::string::npos || dot > slash);
    output = (hasExtension ? input.substr(0, dot) : input) + "_mesh.vtu";
  }

  vtkNew<ErrorCounter> errors;
  vtkNew<vtkXMLPolyDataReader> reader;
  reader->SetFileName(input.c_str());
  reader->AddObserver(vtkCommand::ErrorEvent, errors);

  vtkNew<vtkPhysicalCompressionTriangulator> mesher;
  mesher->SetInputConnection(reader->GetOutputPort());
  mesher->AddObserver(vtkCommand::ErrorEvent, errors);

  vtkNew<vtkXMLUnstructuredGridWriter> writer;
  writer->SetInputConnection(mesher->GetOutputPort(0));
  writer->SetFileName(output.c_str());
  writer->SetDataModeToBinary(); // Debian's ParaView cannot read appended data
  writer->AddObserver(vtkCommand::ErrorEvent, errors);
  if (!writer->Write() || errors->Count > 0)
  {
    std::cerr << input << ": meshing or writing failed (" << errors->Count << " errors)\n";
    return 1;
  }
  vtkUnstructuredGrid* mesh = mesher->GetOutput();
  if (!CheckMesh(mesh, input))
  {
    return 1;
  }

  // Read the file back: what a user opens in ParaView.
  vtkNew<vtkXMLUnstructuredGridReader> check;
  check->SetFileName(output.c_str());
  check->Update();
  if (!CheckMesh(check->GetOutput(), output) ||
    check->GetOutput()->GetNumberOfCells() != mesh->GetNumberOfCells())
  {
    std::cerr << output << ": the written mesh does not read back\n";
    return 1;
  }
  std::cout << input << " -> " << output << ": " << mesh->GetNumberOfCells() << " triangles, "
            << mesh->GetNumberOfPoints() << " vertices\n";
  return 0;
}
