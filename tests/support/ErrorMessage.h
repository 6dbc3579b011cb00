#pragma once
// The message of the exception of type E that f throws ("" when it throws none), for tests
// that check what an error says. Another exception type propagates and fails the test.
#include <string>

namespace aero::test {

template <class E, class F>
std::string messageOf(F f) {
    try {
        f();
    } catch (const E& e) {
        return e.what();
    }
    return "";
}

}  // namespace aero::test
