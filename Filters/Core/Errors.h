// StrataMesh core: typed exceptions. Every precondition of the core is enforced by throwing one
// of these; the VTK adapters catch std::exception and report e.what() through vtkErrorMacro.
#ifndef StrataMeshCore_Errors_h
#define StrataMeshCore_Errors_h

#include <stdexcept>
#include <string>

namespace strata
{

/// The input model is malformed (the message names the cell, point or location at fault).
class InputError : public std::runtime_error
{
public:
  using std::runtime_error::runtime_error;
};

/// A parameter is outside its documented range (the message names it and the range).
class ParameterError : public std::invalid_argument
{
public:
  using std::invalid_argument::invalid_argument;
};

/// The user asked to stop (the progress callback returned false).
class Aborted : public std::runtime_error
{
public:
  Aborted()
    : std::runtime_error("aborted by the user")
  {
  }
};

} // namespace strata

#endif
