// The STEP exchange-structure check (cad/StepText.h): what a well-formed file may contain, and
// each malformation refused with the file, the line and the entity named. The two files that
// crashed OpenCASCADE's loader are replayed from tests/fuzz/corpus/step by fuzz_replay.fuzz_step.
#include <gtest/gtest.h>

#include <string>

#include "cad/StepText.h"
#include "common/Error.h"

namespace aero::cad::step {
namespace {

const std::string kHead =
    "ISO-10303-21;\n"
    "HEADER;\n"
    "FILE_DESCRIPTION(('a model'),'2;1');\n"
    "FILE_NAME('m.stp','2026-12-03',('A. Author'),('Org'),'pre','sys','');\n"
    "FILE_SCHEMA(('AUTOMOTIVE_DESIGN { 1 0 10303 214 1 1 1 1 }'));\n"
    "ENDSEC;\n"
    "DATA;\n";
const std::string kTail = "ENDSEC;\nEND-ISO-10303-21;\n";

std::string failure(const std::string& text) {
    try {
        checkExchangeStructure(text, "part.stp");
    } catch (const InputError& e) {
        return e.what();
    }
    ADD_FAILURE() << "accepted:\n" << text;
    return {};
}

TEST(StepText, AcceptsWhatAWellFormedFileMayContain) {
    const std::string data =
        "/* a comment; with (parentheses) and 'quotes' */\n"
        "#1 = CARTESIAN_POINT('it''s; (a) name',(-1.5,2.,+3.E-2));\n"
        "#2 = DIRECTION('',(0.,0.,1.));\n"
        "#3 = AXIS2_PLACEMENT_3D('',#1,#2,$);\n"
        "#4 = (LENGTH_UNIT() NAMED_UNIT(*) SI_UNIT(.MILLI.,.METRE.));\n"
        "#5 = UNCERTAINTY_MEASURE_WITH_UNIT(LENGTH_MEASURE(1.E-07),#4,'distance','');\n"
        "#6 = SOME_ENTITY(\"0F3A\",(),((1,2),(3,4)),.T.,#7);\n"
        "#7=PLANE('',#3);\n";
    EXPECT_NO_THROW(checkExchangeStructure(kHead + data + kTail, "part.stp"));
    // Two DATA sections (a third-edition file may name them), an empty one, extra header entities.
    const std::string two = "ISO-10303-21;\nHEADER;\nFILE_DESCRIPTION((''),'2;1');\nFILE_NAME('','',(''),(''),'','','');\n"
                            "FILE_SCHEMA(('CONFIG_CONTROL_DESIGN'));\nFILE_POPULATION('x',$,$);\nENDSEC;\n"
                            "DATA('one',('CONFIG_CONTROL_DESIGN'));\n#1=A(#2);\nENDSEC;\nDATA;\n#2=B(1);\nENDSEC;\n"
                            "DATA;\nENDSEC;\nEND-ISO-10303-21;\n";
    EXPECT_NO_THROW(checkExchangeStructure(two, "two.stp"));
    // OpenCASCADE reads a header without FILE_NAME and FILE_DESCRIPTION: so do we.
    EXPECT_NO_THROW(checkExchangeStructure(
        "ISO-10303-21;\nHEADER;\nFILE_SCHEMA(('CONFIG_CONTROL_DESIGN'));\nENDSEC;\nDATA;\n#1=A(1);\n" + kTail,
        "schema_only.stp"));
}

TEST(StepText, RefusesMalformedFilesNamingTheLineAndTheEntity) {
    struct Case {
        std::string data;  // between DATA; and ENDSEC;
        std::string message;
    };
    // The first data statement is on line 8.
    const Case cases[] = {
        {"#1 = A(1,,2);\n", "line 8, entity #1: expected a parameter, found ',' (an empty list element)"},
        {"#1 = A((1, ),2);\n", "entity #1: expected a parameter, found ')' (an empty list element)"},
        {"#1 = A(1));\n", "entity #1: expected ';' at the end of the entity instance, found ')'"},
        {"#1 = A(1)\n#2 = B(2);\n", "line 9, entity #1: expected ';' at the end of the entity instance, found an entity name"},
        {"#1 = A('open);\n", "line 8, entity #1: a string is not closed"},
        {"#1 = A(1);\n/* open\n", "line 9: a comment (/*) is not closed"},
        {"#1 = A(1);\n#1 = B(2);\n", "line 9, entity #1: is defined twice"},
        {"#1 = A(#2, #3);\n#2 = B(#4);\n", "line 8, entity #1: refers to #3, which the file does not define (2 such "
                                            "references in the file)"},
        {"#1 = A(.T);\n", "entity #1: an enumeration value (.X.) is not closed"},
        {"#1 = A(#);\n", "entity #1: '#' is not followed by an entity number"},
        {"#1 = A(1.5E);\n", "entity #1: a number's exponent has no digits"},
        {"#1 = A(1) B(2);\n", "entity #1: expected ';' at the end of the entity instance, found 'B'"},
        {"#1 = ();\n", "entity #1: a complex entity instance has no partial entities"},
        {"#1 = A(1 2);\n", "entity #1: expected ',' or ')' in a parameter list, found a number"},
        {"#1 = A(1);\n#2 A(2);\n", "line 9, entity #2: expected '=' after the entity name"},
        {"#1 = A(1 & 2);\n", "line 8, entity #1: unexpected character '&'"},
        {std::string("#1 = A(1,\x01);\n"), "unexpected byte 0x01 outside a string"},
        {"#12345678901234567890 = A(1);\n", "an entity name has more than 18 digits"},
    };
    for (const Case& c : cases) {
        const std::string m = failure(kHead + c.data + kTail);
        EXPECT_NE(m.find("STEP file 'part.stp', "), std::string::npos) << m;
        EXPECT_NE(m.find(c.message), std::string::npos) << "for\n" << c.data << "got: " << m;
    }

    // The structure around the data.
    EXPECT_NE(failure("ISO-10303-21;\nHEADER;\nFILE_NAME('a','b'));\nENDSEC;\n").find(
                  "line 3: expected ';' after a header entity, found ')'"),
              std::string::npos);
    EXPECT_NE(failure(kHead + "#1 = A(1);\n").find("line 9: the file ends inside the DATA section (truncated?)"),
              std::string::npos);
    EXPECT_NE(failure(kHead + "#1 = A(1);\nENDSEC;\n").find("the file ends without END-ISO-10303-21; (truncated?)"),
              std::string::npos);
    EXPECT_NE(failure("ISO-10303-21;\nHEADER;\nFILE_SCHEMA(('X'));\n").find("the file ends inside the header"),
              std::string::npos);
    EXPECT_NE(failure("ISO-10303-21;\nHEADER;\nENDSEC;\n" + kTail).find("expected a DATA section after the header"),
              std::string::npos);
    EXPECT_NE(failure("ISO-10303-21;\nDATA;\n" + kTail).find("expected HEADER; after ISO-10303-21;"), std::string::npos);
}

TEST(StepText, DeepNestingIsRefusedWithoutExhaustingTheStack) {
    // A hostile file of a million open parentheses: refused at the depth limit, not a stack overflow.
    const std::string deep = kHead + "#1 = A(" + std::string(1000000, '(') + "1" + std::string(1000000, ')') + ");\n" + kTail;
    EXPECT_NE(failure(deep).find("parameters nested deeper than 200 lists"), std::string::npos);
    // Real files nest a few levels (a B-spline surface's poles: two).
    const std::string fine = kHead + "#1 = A(" + std::string(50, '(') + "1" + std::string(50, ')') + ");\n" + kTail;
    EXPECT_NO_THROW(checkExchangeStructure(fine, "fine.stp"));
}

// Found by fuzz_step, 2026-12-05: an oriented edge that is its own edge element made
// OpenCASCADE's reader recurse (EdgeStart / EdgeEnd) until the stack overflowed, a segmentation
// fault of `aeroform-cli info`. References must not form a cycle: refused, naming the cycle.
TEST(StepText, ACycleOfReferencesIsRefusedNamingIt) {
    EXPECT_NE(failure(kHead + "#1 = VERTEX_POINT('',#2);\n#2 = CARTESIAN_POINT('',(0.,0.,0.));\n"
                              "#84 = ORIENTED_EDGE('',*,*,#84,.F.);\n" + kTail)
                  .find("line 10, entity #84: refers to itself (#84 -> #84)"),
              std::string::npos)
        << failure(kHead + "#84 = ORIENTED_EDGE('',*,*,#84,.F.);\n" + kTail);
    const std::string m = failure(kHead + "#1 = A(#2,#4);\n#2 = B(#3);\n#3 = C((#5,#1));\n#4 = D(1);\n#5 = E(2);\n" + kTail);
    EXPECT_NE(m.find("entity #1: is part of a cycle of references (#1 -> #2 -> #3 -> #1)"), std::string::npos) << m;
    // A long cycle is named by its ends.
    std::string ring;
    for (int i = 1; i <= 20; ++i) ring += "#" + std::to_string(i) + " = R(#" + std::to_string(i % 20 + 1) + ");\n";
    const std::string r = failure(kHead + ring + kTail);
    EXPECT_NE(r.find("(#1 -> #2 -> #3 -> #4 -> ... (14 more) -> #19 -> #20 -> #1)"), std::string::npos) << r;
    // Shared references without a cycle (a diamond) are fine.
    EXPECT_NO_THROW(checkExchangeStructure(kHead + "#1 = A(#2,#3);\n#2 = B(#4);\n#3 = C(#4);\n#4 = D(1);\n" + kTail, "d.stp"));
}

}  // namespace
}  // namespace aero::cad::step
