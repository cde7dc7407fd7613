// The exact text of each kind of error: a person reads these, so they are part of the interface.
#include <gtest/gtest.h>

#include "test_util.h"

using odec::test::Session;

namespace {

std::string error_of(const std::string& text) {
    Session s;
    EXPECT_FALSE(s.run(text)) << text;
    return s.error();
}

} // namespace

TEST(Errors, UnknownCommandSuggestsTheClosest) {
    EXPECT_EQ(error_of("stpe 10"),
              "t.dat:1:1: error: unknown command 'stpe'\n"
              "    stpe 10\n"
              "    ^~~~\n"
              "  did you mean 'step'?\n"
              "  type 'help' for the list of commands\n");
}

TEST(Errors, UnknownKeywordListsWhatIsExpected) {
    EXPECT_EQ(error_of("grav 0 0 -10\nset dtfarc 0.1"),
              "t.dat:2:5: error: unknown keyword 'dtfarc' for 'set'\n"
              "    set dtfarc 0.1\n"
              "        ^~~~~~\n"
              "  did you mean 'dtfrac'?\n"
              "  expected one of: dt, dtfrac, ctol, ovtol, flow, substeps, echo, log, logfile, gravity, ncyc, jmat, jcons, plot, dynamic, threads, energy, large, small\n"
              "  see 'help set'\n");
}

TEST(Errors, AmbiguousAbbreviation) {
    EXPECT_EQ(error_of("hist zd 0,0,0"),
              "t.dat:1:6: error: abbreviation 'zd' is too short: write at least 'zdis'\n"
              "    hist zd 0,0,0\n"
              "         ^~\n"
              "  see 'help history'\n");
    EXPECT_EQ(error_of("damp l"),
              "t.dat:1:6: error: abbreviation 'l' is too short: write at least 'loc'\n"
              "    damp l\n"
              "         ^\n"
              "  see 'help damping'\n");
    EXPECT_EQ(error_of("pr mat=1"),
              "t.dat:1:1: error: abbreviation 'pr' is too short: write at least 'prop' or 'pri'\n"
              "    pr mat=1\n"
              "    ^~\n"
              "  type more letters of the command\n");
}

TEST(Errors, AmbiguousBetweenTwoValidKeywords) {
    // 'dt' is exact; 'dtf' selects dtfrac; 'hist x...' with 4 letters is unique. 'prop j...' with
    // 'jdi' is unique; 'jd' is too short for both joint keywords starting with it.
    EXPECT_EQ(error_of("prop jmat=1 jd 5"),
              "t.dat:1:13: error: abbreviation 'jd' is too short: write at least 'jdi'\n"
              "    prop jmat=1 jd 5\n"
              "                ^~\n"
              "  see 'help property'\n");
}

TEST(Errors, MissingValue) {
    EXPECT_EQ(error_of("prop mat=1 dens"),
              "t.dat:1:16: error: missing value for 'density': expected a number\n"
              "    prop mat=1 dens\n"
              "                   ^\n"
              "  'density' takes: density rho\n"
              "  see 'help property'\n");
}

TEST(Errors, WrongType) {
    EXPECT_EQ(error_of("prop mat=1 dens=heavy"),
              "t.dat:1:17: error: 'heavy' is not a number: 'density' expects rho (a number)\n"
              "    prop mat=1 dens=heavy\n"
              "                    ^~~~~\n"
              "  'density' takes: density rho\n"
              "  see 'help property'\n");
    EXPECT_EQ(error_of("step 1.5"),
              "t.dat:1:6: error: '1.5' is not an integer: 'step' expects n (an integer)\n"
              "    step 1.5\n"
              "         ^~~\n"
              "  see 'help step'\n");
}

TEST(Errors, OutOfRange) {
    EXPECT_EQ(error_of("prop mat=1 dens=-5"),
              "t.dat:1:17: error: 'density' must be > 0 (got -5)\n"
              "    prop mat=1 dens=-5\n"
              "                    ^~\n"
              "  see 'help property'\n");
    EXPECT_EQ(error_of("damp local 1.2"),
              "t.dat:1:12: error: 'local' must be >= 0 and < 1 (got 1.2)\n"
              "    damp local 1.2\n"
              "               ^~~\n"
              "  see 'help damping'\n");
}

TEST(Errors, ExtraWords) {
    EXPECT_EQ(error_of("grav 0 0 -10 5"),
              "t.dat:1:14: error: extra word '5': 'gravity' takes nothing more\n"
              "    grav 0 0 -10 5\n"
              "                 ^\n"
              "  see 'help gravity'\n");
    EXPECT_EQ(error_of("new now"),
              "t.dat:1:5: error: extra word 'now': 'new' takes nothing more\n"
              "    new now\n"
              "        ^~~\n"
              "  see 'help new'\n");
}

TEST(Errors, UnterminatedString) {
    EXPECT_EQ(error_of("title 'Slope"),
              "t.dat:1:7: error: unterminated string: no closing ' on this line\n"
              "    title 'Slope\n"
              "          ^~~~~~\n"
              "  expected the string to end with ' before the end of the line\n");
}

TEST(Errors, MissingFileInCall) {
    EXPECT_EQ(error_of("call 'no-such-file.dat'"),
              "t.dat:1:6: error: cannot open 'no-such-file.dat': No such file or directory\n"
              "    call 'no-such-file.dat'\n"
              "         ^~~~~~~~~~~~~~~~~~\n"
              "  see 'help call'\n");
}

TEST(Errors, CallRecursion) {
    const std::string dir = std::string(ODEC_SOURCE_DIR) + "/tests/scripts/";
    Session s;
    EXPECT_FALSE(s.interp.run_file(dir + "recursion-a.dat"));
    EXPECT_EQ(s.error(), dir + "recursion-b.dat:2:6: error: '" + dir + "recursion-a.dat' calls itself (" + dir +
                             "recursion-a.dat -> " + dir + "recursion-b.dat -> " + dir + "recursion-a.dat)\n"
                             "    call 'recursion-a.dat'\n"
                             "         ^~~~~~~~~~~~~~~~~\n"
                             "  a file may not call a file that is still running\n"
                             "  see 'help call'\n");
}

TEST(Errors, RequiredChoiceAndMisplacedProperty) {
    EXPECT_EQ(error_of("poly region 1"),
              "t.dat:1:14: error: 'poly' needs one of: brick, prism, face, tetra, tunnel\n"
              "    poly region 1\n"
              "                 ^\n"
              "  see 'help poly'\n");
    EXPECT_EQ(error_of("prop mat 1 jkn 5e9"),
              "t.dat:1:12: error: 'jkn' is a joint property: give it with 'jmat=n'\n"
              "    prop mat 1 jkn 5e9\n"
              "               ^~~\n"
              "  see 'help property'\n");
}

TEST(Errors, RangeFilters) {
    EXPECT_EQ(error_of("fix range q 1"),
              "t.dat:1:11: error: unknown range filter 'q'\n"
              "    fix range q 1\n"
              "              ^\n"
              "  expected one of: x, y, z, region, group, id, bid, xr, yr, zr, sphere, cylinder, plane, nrange, union, not\n"
              "  see 'help range'\n");
    EXPECT_EQ(error_of("fix range"),
              "t.dat:1:10: error: missing range filter after 'range'\n"
              "    fix range\n"
              "             ^\n"
              "  expected one of: x, y, z, region, group, id, bid, xr, yr, zr, sphere, cylinder, plane, nrange, union, not\n"
              "  see 'help range'\n");
}

TEST(Errors, KeywordGivenTwiceAndExclusiveChoices) {
    EXPECT_EQ(error_of("prop mat=1 dens 1 dens 2"),
              "t.dat:1:19: error: 'density' given twice\n"
              "    prop mat=1 dens 1 dens 2\n"
              "                      ^~~~\n"
              "  it was first given at column 12\n"
              "  see 'help property'\n");
    EXPECT_EQ(error_of("damp local off"),
              "t.dat:1:12: error: 'off' cannot be combined with 'local'\n"
              "    damp local off\n"
              "               ^~~\n"
              "  give one of: local, auto, mass, off\n"
              "  see 'help damping'\n");
}

TEST(Errors, NoTimestepAndNoMass) {
    EXPECT_EQ(error_of("poly brick 0 1 0 1 0 1\nprop mat=1 dens=1000\nstep 10"),
              "t.dat:3:1: error: no timestep: there are no contacts or zones to set one, so give it with 'set dt'\n"
              "    step 10\n"
              "    ^~~~\n"
              "  see 'help step'\n");
    EXPECT_EQ(error_of("poly brick 0 1 0 1 0 1\nset dt 1e-3\nstep 10"),
              "t.dat:3:1: error: block 1 has no mass: material 1 is not defined (give one with 'prop mat=1 dens=...')\n"
              "    step 10\n"
              "    ^~~~\n"
              "  see 'help step'\n");
}

TEST(Errors, AFailedCommandChangesNothing) {
    Session s;
    ASSERT_TRUE(s.run("poly brick 0 1 0 1 0 1\nprop mat=1 dens=2000\ngrav 0 0 -10"));
    const double mass = s.model.blocks.mass[0];
    // Each of these fails after some of its words were valid.
    EXPECT_FALSE(s.run("prop mat=1 dens=3000 jkn 5"));
    EXPECT_FALSE(s.run("prop mat=1 dens=3000 ymod 1e9"));
    EXPECT_FALSE(s.run("poly brick 0 1 0 1 1 0 region 5"));
    EXPECT_FALSE(s.run("damp 0.05 local"));
    EXPECT_FALSE(s.run("hist zdis 0,0,0 label 4 'x'"));
    EXPECT_EQ(s.model.blocks.size(), 1);
    EXPECT_EQ(s.model.blocks.mass[0], mass);
    EXPECT_EQ(s.model.materials[1].density, 2000);
    EXPECT_EQ(s.model.damping.mode, odec::DampingMode::Local);
    EXPECT_TRUE(s.model.histories.items.empty());
}

TEST(Errors, AScriptStopsAtTheFirstError) {
    Session s;
    EXPECT_FALSE(s.run("grav 0 0 -10\nbogus\ngrav 0 0 -5"));
    EXPECT_EQ(s.model.gravity.z(), -10);
}

TEST(Errors, ABlowUpStopsCyclingAndNamesTheBlock) {
    Session s;
    // An absurd load drives a block faster than anything in rock mechanics can move. (A load
    // that would move it past the base in the very first step is refused before stepping:
    // see numbers_test.cpp.)
    ASSERT_TRUE(s.run("poly brick 0 1 0 1 -1 0 region 1\npoly brick 0 1 0 1 0 1\nprop mat=1 dens=2000\n"
                      "grav 0 0 -10\nfix range region 1\ndamp off\nset dt 1e-3\nbound zload -5e8 range id 2"));
    EXPECT_FALSE(s.run("step 100000"));
    EXPECT_NE(s.error().find("error: stopped: the motion of block 2 has run away (step "), std::string::npos) << s.error();
    EXPECT_NE(s.error().find("the model is left as it was at that step, for inspection"), std::string::npos);
    EXPECT_LT(s.model.step, 100000);
    // The model can still be inspected.
    EXPECT_TRUE(s.run("print block\nprint info"));
}

TEST(Errors, PolyNamesTheFaceThatIsNotPlanar) {
    EXPECT_EQ(error_of("poly face (0,0,0) (1,0,0) (1,1,0.2) (0,1,0) &\n"
                       "     face (0,0,1) (1,0,1) (1,1,1) (0,1,1) face (0,0,0) (1,0,0) (1,0,1) (0,0,1) &\n"
                       "     face (1,0,0) (1,1,0) (1,1,1) (1,0,1) face (1,1,0) (0,1,0) (0,1,1) (1,1,1) &\n"
                       "     face (0,1,0) (0,0,0) (0,0,1) (0,1,1)"),
              "t.dat:1:6: error: face 1 is not planar\n"
              "    poly face (0,0,0) (1,0,0) (1,1,0.2) (0,1,0) &\n"
              "         ^~~~\n"
              "  see 'help poly'\n");
}

TEST(Errors, PolyNamesTheFaceThatCrossesItself) {
    // A cube whose top is pushed down in the middle (a roof valley) is a solid, if not a convex
    // one: it is made of joined convex blocks, the cube less a square pyramid 0.5 m high. An
    // L-shaped block whose bottom lists two corners the wrong way round bounds no solid: the
    // error points at that face.
    Session s;
    ASSERT_TRUE(s.run("poly face (0,0,0) (0,1,0) (1,1,0) (1,0,0) face (0,0,1) (1,0,1) (0.5,0.5,0.5) "
                      "face (1,0,1) (1,1,1) (0.5,0.5,0.5) face (1,1,1) (0,1,1) (0.5,0.5,0.5) "
                      "face (0,1,1) (0,0,1) (0.5,0.5,0.5) face (0,0,0) (1,0,0) (1,0,1) (0,0,1) "
                      "face (1,0,0) (1,1,0) (1,1,1) (1,0,1) face (1,1,0) (0,1,0) (0,1,1) (1,1,1) "
                      "face (0,1,0) (0,0,0) (0,0,1) (0,1,1)"))
        << s.error();
    const int built = s.model.blocks.size();
    EXPECT_GE(built, 2);
    double volume = 0;
    for (int b = 0; b < built; ++b) volume += s.model.blocks.volume[b];
    EXPECT_NEAR(volume, 5.0 / 6, 1e-14);
    EXPECT_FALSE(s.run("poly face (0,0,0) (2,1,0) (2,0,0) (1,1,0) (1,2,0) (0,2,0) &\n"
                       "  face (0,0,1) (2,0,1) (2,1,1) (1,1,1) (1,2,1) (0,2,1) &\n"
                       "  face (0,0,0) (2,0,0) (2,0,1) (0,0,1)  face (2,0,0) (2,1,0) (2,1,1) (2,0,1) &\n"
                       "  face (2,1,0) (1,1,0) (1,1,1) (2,1,1)  face (1,1,0) (1,2,0) (1,2,1) (1,1,1) &\n"
                       "  face (1,2,0) (0,2,0) (0,2,1) (1,2,1)  face (0,2,0) (0,0,0) (0,0,1) (0,2,1)"));
    EXPECT_EQ(s.error(), "t.dat:1:6: error: face 1 crosses itself\n"
                         "    poly face (0,0,0) (2,1,0) (2,0,0) (1,1,0) (1,2,0) (0,2,0) &\n"
                         "         ^~~~\n"
                         "  see 'help poly'\n");
    EXPECT_EQ(s.model.blocks.size(), built);
}

TEST(Errors, CommandsThatNeedSomethingToDoSaySo) {
    EXPECT_NE(error_of("change range z 0 1").find("t.dat:1:1: error: 'change' needs 'mat=n', 'cons=c', 'jmat=n' or 'jcons=j'"),
              std::string::npos);
    EXPECT_NE(error_of("ini range z 0 1").find("t.dat:1:1: error: 'initial' needs one of: xvel, yvel, zvel"),
              std::string::npos);
    EXPECT_NE(error_of("reset").find("t.dat:1:1: error: 'reset' needs what to reset: displacement, jdisp, time, "
                                     "history, velocity or energy"),
              std::string::npos);
    EXPECT_NE(error_of("bound range z 0 1").find("error: 'boundary' needs a velocity (xvel ...), a load (xload ...), a moment (xmoment ...), 'stress' or 'free'"),
              std::string::npos);
    EXPECT_NE(error_of("excavate").find("t.dat:1:1: error: 'excavate' needs a range"), std::string::npos);
    EXPECT_NE(error_of("damp").find("t.dat:1:1: error: 'damping' needs one of: local, auto, mass, off"), std::string::npos);
    EXPECT_NE(error_of("damp 0.05 mass").find("error: 'damp ... mass' needs the critical damping fraction and the frequency"),
              std::string::npos);
    EXPECT_NE(error_of("set small large").find("error: 'small' and 'large' exclude each other"), std::string::npos);
    EXPECT_NE(error_of("change jcons 3").find("error: 'jcons' must be 1 to 2 (got 3)"), std::string::npos);
    EXPECT_NE(error_of("poly prism a (0,0,0) (1,0,0) (0,1,0)").find("error: 'prism' needs both ends"), std::string::npos);
    EXPECT_NE(error_of("poly brick 0 1 0 1 0 1 a (0,0,0)").find("error: 'a' goes with 'prism'"), std::string::npos);
}

TEST(Errors, AHistoryThatDoesNotExistIsNamedTheSameEverywhere) {
    EXPECT_EQ(error_of("hist time\nprint hist 1 2"),
              "t.dat:2:14: error: there is no history 2 (there is 1)\n"
              "    print hist 1 2\n"
              "                 ^\n"
              "  make histories with 'hist', e.g. 'hist zdis 0,0,1'\n"
              "  see 'help print'\n");
    EXPECT_NE(error_of("hist label 3 'x'").find("t.dat:1:12: error: there is no history 3 (there are 0)"),
              std::string::npos);
}
