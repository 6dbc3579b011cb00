#pragma once
// Exception hierarchy of libcore (STYLE.md principle 7).
//   Error            root of everything libcore throws on bad input
//   InputError       a file cannot be read or is malformed (names the file)
//   GeometryError    a geometric entity is invalid (names the entity)
//   CaseError        a case file has a bad key, type or value (names the key)
// Internal invariants use AERO_ASSERT (debug builds only); solvers return a status.
#include <cassert>
#include <stdexcept>
#include <string>

namespace aero {

class Error : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

class InputError : public Error {
public:
    using Error::Error;
};

class GeometryError : public Error {
public:
    using Error::Error;
};

class CaseError : public Error {
public:
    using Error::Error;
};

}  // namespace aero

#define AERO_ASSERT(cond) assert(cond)
