#include "optimize/Optimizer.h"

#include <stdexcept>

namespace aero::optimize {

std::unique_ptr<Optimizer> makeIpopt();  // Ipopt.cpp
std::unique_ptr<Optimizer> makeSlsqp();  // Slsqp.cpp

namespace {

struct Entry {
    const char* name;
    std::unique_ptr<Optimizer> (*make)();
};
const Entry kTable[] = {{"ipopt", makeIpopt}, {"slsqp", makeSlsqp}};

}  // namespace

std::unique_ptr<Optimizer> makeOptimizer(const std::string& name) {
    std::string list;
    for (const Entry& e : kTable) {
        if (name == e.name) return e.make();
        list += std::string(list.empty() ? "" : ", ") + e.name;
    }
    throw std::invalid_argument("unknown optimizer '" + name + "' (expected " + list + ")");
}

const std::vector<std::string>& optimizerNames() {
    static const std::vector<std::string> names = [] {
        std::vector<std::string> v;
        for (const Entry& e : kTable) v.push_back(e.name);
        return v;
    }();
    return names;
}

}  // namespace aero::optimize
