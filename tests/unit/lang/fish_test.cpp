// FISH: the classic dialect's statements, operators, intrinsics, model access and errors, run
// through the real interpreter as a script would run them.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "fish/runtime.h"
#include "test_util.h"

using odec::test::Session;

namespace {

// The value of a FISH global after the script ran.
odec::fish::Value global(Session& s, const std::string& name) {
    const odec::fish::Symbol* sym = s.interp.fish().find(name);
    EXPECT_NE(sym, nullptr) << name;
    return sym ? sym->value : odec::fish::Value::null();
}

double number(Session& s, const std::string& name) { return global(s, name).number(); }

} // namespace

TEST(Fish, ArithmeticFollowsTheClassicRules) {
    Session s;
    ASSERT_TRUE(s.run("def f\n"
                      "  a = 7 / 2\n"          // integer division truncates
                      "  b = 7.0 / 2\n"
                      "  c = -2^2\n"           // power binds tighter than the sign
                      "  d = 2^3^2\n"          // and groups to the right
                      "  e = 1 + 2 * 3 - 4\n"
                      "  g = (1 + 2) * 3\n"
                      "  h = 2^0.5\n"
                      "  k = 9223372036854775807 + 1\n" // overflow turns to float, not wraps
                      "  m = -7 / 2\n"
                      "end\n@f"))
        << s.error();
    EXPECT_EQ(global(s, "a").type, odec::fish::Type::Int);
    EXPECT_EQ(number(s, "a"), 3);
    EXPECT_EQ(number(s, "b"), 3.5);
    EXPECT_EQ(number(s, "c"), -4);
    EXPECT_EQ(number(s, "d"), 512);
    EXPECT_EQ(number(s, "e"), 3);
    EXPECT_EQ(number(s, "g"), 9);
    EXPECT_NEAR(number(s, "h"), std::sqrt(2.0), 1e-15);
    EXPECT_EQ(global(s, "k").type, odec::fish::Type::Float);
    EXPECT_NEAR(number(s, "k"), 9.223372036854775808e18, 1e4);
    EXPECT_EQ(number(s, "m"), -3);
}

TEST(Fish, ComparisonsAndLogic) {
    Session s;
    ASSERT_TRUE(s.run("def f\n"
                      "  a = 0\n  b = 0\n  c = 0\n  d = 0\n"
                      "  if 2 = 2 then\n    a = 1\n  endif\n"
                      "  if 2 # 3 & 1 < 2 then\n    b = 1\n  endif\n"
                      "  if 1 > 2 | 3 >= 3 then\n    c = 1\n  endif\n"
                      "  if not (1 = 1) then\n    d = 1\n  else\n    d = 2\n  endif\n"
                      "  e = 'abc' = 'abc'\n"
                      "end\n@f"))
        << s.error();
    EXPECT_EQ(number(s, "a"), 1);
    EXPECT_EQ(number(s, "b"), 1);
    EXPECT_EQ(number(s, "c"), 1);
    EXPECT_EQ(number(s, "d"), 2);
    EXPECT_EQ(global(s, "e").type, odec::fish::Type::Bool);
    EXPECT_EQ(number(s, "e"), 1);
}

TEST(Fish, IfElseIfChains) {
    Session s;
    ASSERT_TRUE(s.run("def grade(x)\n"
                      "  if x > 10 then\n    grade = 3\n  else if x > 5 then\n    grade = 2\n  else\n    grade = 1\n  endif\n"
                      "end\n"
                      "def f\n  a = grade(20)\n  b = grade(7)\n  c = grade(1)\nend\n@f"))
        << s.error();
    EXPECT_EQ(number(s, "a"), 3);
    EXPECT_EQ(number(s, "b"), 2);
    EXPECT_EQ(number(s, "c"), 1);
}

TEST(Fish, LoopsSectionsAndCases) {
    Session s;
    ASSERT_TRUE(s.run("def f\n"
                      "  sum = 0\n"
                      "  loop i (1, 100)\n    sum = sum + i\n  endloop\n"
                      "  n = 0\n"
                      "  loop while n < 7\n    n = n + 2\n  end_loop\n"
                      "  s2 = 0\n"
                      "  loop k (1, 10)\n    if k = 4\n      exit loop\n    endif\n    s2 = s2 + k\n  endloop\n"
                      "  reached = 0\n"
                      "  section\n    reached = 1\n    exit section\n    reached = 2\n  endsection\n"
                      "  word = ''\n"
                      "  loop j (1, 3)\n"
                      "    caseof j\n    case 1\n      word = word + 'a'\n    case 2, 3\n      word = word + 'b'\n    endcase\n"
                      "  endloop\n"
                      "  empty = 0\n"
                      "  loop j (5, 1)\n    empty = empty + 1\n  endloop\n"
                      "end\n@f"))
        << s.error();
    EXPECT_EQ(number(s, "sum"), 5050);
    EXPECT_EQ(number(s, "n"), 8);
    EXPECT_EQ(number(s, "s2"), 6);
    EXPECT_EQ(number(s, "reached"), 1);
    EXPECT_EQ(global(s, "word").s, "abb");
    EXPECT_EQ(number(s, "empty"), 0);
}

TEST(Fish, LocalsStayLocalAndGlobalsAreShared) {
    Session s;
    ASSERT_TRUE(s.run("def inner(x)\n  local t = x * 2\n  shared = t\n  inner = t + 1\nend\n"
                      "def outer\n  t = 5\n  r = inner(10)\nend\n@outer"))
        << s.error();
    EXPECT_EQ(number(s, "t"), 5);       // the global t is not inner's local t
    EXPECT_EQ(number(s, "shared"), 20);
    EXPECT_EQ(number(s, "r"), 21);
}

TEST(Fish, AFunctionNamedAloneIsCalledAndGivesItsValue) {
    // As the classic scripts use them: constants defined as functions, read by name.
    Session s;
    ASSERT_TRUE(s.run("def span\n  span = 12\nend\n"
                      "def voussoir\n  voussoir = 21\nend\n"
                      "def edge_length\n  edge_length = 0.5*span*Pi/voussoir\nend\n"
                      "def j_normal\n  j_normal = 36e9/edge_length\nend\n"
                      "prop jmat 3 jkn @j_normal jks 1e9 jfric 43\n"
                      "def check\n  v = j_normal\nend\n@check"))
        << s.error();
    EXPECT_NEAR(number(s, "v"), 36e9 / (0.5 * 12 * M_PI / 21), 1e-3);
    EXPECT_NEAR(s.model.joint_materials.at(3).kn, 36e9 / (0.5 * 12 * M_PI / 21), 1e-3);
}

TEST(Fish, StringsAndConversions) {
    Session s;
    ASSERT_TRUE(s.run("def f\n"
                      "  a = 'x' + string(3) + \"y\" + string(2.5) + string(2.0)\n"
                      "  b = float('1e-0')\n"
                      "  c = int(-3.7)\n"
                      "  d = strlen('hello')\n"
                      "  e = substr('abcdef', 2, 3)\n"
                      "  g = string(vector(1,2,3))\n"
                      "  h = round(2.5)\n"
                      "end\n@f"))
        << s.error();
    EXPECT_EQ(global(s, "a").s, "x3y2.52.0");
    EXPECT_EQ(number(s, "b"), 1.0);
    EXPECT_EQ(global(s, "b").type, odec::fish::Type::Float);
    EXPECT_EQ(number(s, "c"), -3);
    EXPECT_EQ(number(s, "d"), 5);
    EXPECT_EQ(global(s, "e").s, "bcd");
    EXPECT_EQ(global(s, "g").s, "(1.0,2.0,3.0)");
    EXPECT_EQ(number(s, "h"), 3);
}

TEST(Fish, MathIntrinsicsUseRadians) {
    Session s;
    ASSERT_TRUE(s.run("def f\n"
                      "  a = sin(pi/6)\n  b = cos(0)\n  c = atan2(1, 1)\n  d = sqrt(16)\n  e = abs(-3)\n"
                      "  g = min(3, 1.5, 2)\n  h = max(1, 5, 2)\n  k = exp(0)\n  l = ln(exp(2))\n  m = log(1000)\n"
                      "  n = sgn(-2)\n  p = 30 * degrad\n  q = mag(vector(3,4,0))\n  r = dot(vector(1,2,3), vector(4,5,6))\n"
                      "  w = zcomp(cross(vector(1,0,0), vector(0,1,0)))\n"
                      "end\n@f"))
        << s.error();
    EXPECT_NEAR(number(s, "a"), 0.5, 1e-15);
    EXPECT_EQ(number(s, "b"), 1);
    EXPECT_NEAR(number(s, "c"), M_PI / 4, 1e-15);
    EXPECT_EQ(number(s, "d"), 4);
    EXPECT_EQ(number(s, "e"), 3);
    EXPECT_EQ(number(s, "g"), 1.5);
    EXPECT_EQ(number(s, "h"), 5);
    EXPECT_EQ(number(s, "k"), 1);
    EXPECT_NEAR(number(s, "l"), 2, 1e-15);
    EXPECT_NEAR(number(s, "m"), 3, 1e-15);
    EXPECT_EQ(number(s, "n"), -1);
    EXPECT_NEAR(number(s, "p"), M_PI / 6, 1e-15);
    EXPECT_EQ(number(s, "q"), 5);
    EXPECT_EQ(number(s, "r"), 32);
    EXPECT_EQ(number(s, "w"), 1);
}

TEST(Fish, ArraysAreSizedWhenTheFunctionIsDefined) {
    // A classic pattern: the size comes from a variable set by an earlier call, and the
    // declaration may sit inside a loop without clearing the array.
    Session s;
    ASSERT_TRUE(s.run("def setn\n  n = 4\nend\n@setn\n"
                      "def fill\n"
                      "  loop i (1, n)\n    array a(n, 2)\n    a(i, 1) = i * i\n    a(i, 2) = 'r' + string(i)\n  endloop\n"
                      "  total = 0\n  loop i (1, n)\n    total = total + a(i, 1)\n  endloop\n"
                      "  last = a(n, 2)\n"
                      "end\n@fill"))
        << s.error();
    EXPECT_EQ(number(s, "total"), 1 + 4 + 9 + 16);
    EXPECT_EQ(global(s, "last").s, "r4");
    // Out of bounds is an error naming the array and its bounds.
    EXPECT_FALSE(s.run("def bad\n  x = a(5, 1)\nend\n@bad"));
    EXPECT_NE(s.error().find("index 5 is outside array 'a' (1 to 4)"), std::string::npos) << s.error();
}

TEST(Fish, CommandBlocksSubstituteValues) {
    Session s;
    ASSERT_TRUE(s.run("def wall(n)\n"
                      "  loop k (1, n)\n"
                      "    z1 = k - 1\n    z2 = k\n"
                      "    command\n      poly brick 0 1 0 1 @z1 @z2 region @k\n    endcommand\n"
                      "  endloop\n"
                      "end\n@wall(3)"))
        << s.error();
    ASSERT_EQ(s.model.blocks.size(), 3);
    EXPECT_NEAR(s.model.blocks.centroid[2].z(), 2.5, 1e-12);
    EXPECT_EQ(s.model.blocks.region[2], 3);
}

TEST(Fish, AtWordsInCommandsTakeTheirValues) {
    Session s;
    ASSERT_TRUE(s.run("def setup\n  x2 = 2.5\n  name = 'walls'\n  gz = -9.81\n  g = vector(0, 0, gz)\nend\n@setup\n"
                      "poly brick 0 @x2 0 1 0 1\n"
                      "grav @g\n"
                      "save @name"))
        << s.error();
    EXPECT_NEAR(s.model.blocks.centroid[0].x(), 1.25, 1e-12);
    EXPECT_NEAR(s.model.gravity.z(), -9.81, 1e-15);
    std::ifstream saved("walls.sav");
    EXPECT_TRUE(saved.good()) << "save @name writes the file the variable names";
    std::remove("walls.sav");
    // An unknown name is an error at its word.
    EXPECT_FALSE(s.run("poly brick 0 @nothing 0 1 0 1"));
    EXPECT_NE(s.error().find("t.dat:1:14: error: '@nothing' is no FISH variable or function"), std::string::npos) << s.error();
}

TEST(Fish, TopLevelStatementsAndBareCalls) {
    Session s;
    ASSERT_TRUE(s.run("@a = 3\n"
                      "def twice(v)\n  twice = 2 * v\nend\n"
                      "@b = twice(@a)\n"
                      "def setc\n  c = 7\nend\n"
                      "setc\n"))   // UDEC calls a function by its name alone
        << s.error();
    EXPECT_EQ(number(s, "a"), 3);
    EXPECT_EQ(number(s, "b"), 6);
    EXPECT_EQ(number(s, "c"), 7);
}

TEST(Fish, VectorArgumentsInACall) {
    Session s;
    ASSERT_TRUE(s.run("@px = 1\n@py = 2\n@pz = 3\n"
                      "def get(v)\n  got = v\nend\n"
                      "@get( (@px, @py, @pz) )"))
        << s.error();
    EXPECT_EQ(global(s, "got").type, odec::fish::Type::Vector);
    EXPECT_EQ(global(s, "got").v, Eigen::Vector3d(1, 2, 3));
}

TEST(Fish, WalksOverBlocksAndContactsReadTheModel) {
    // A block resting on a fixed base: the contact forces summed by FISH equal its weight.
    Session s;
    ASSERT_TRUE(s.run("poly brick 0 2 0 2 -1 0\npoly brick 0.5 1.5 0.5 1.5 0 1\n"
                      "prop mat=1 dens=2000\nprop jmat=1 jkn=1e10 jks=1e10 jfric=30\n"
                      "grav 0 0 -10\nfix range z -1 0\nsolve ratio 1e-7\n"
                      "def sums\n"
                      "  nb = 0\n  vol = 0\n  local b = block_head\n"
                      "  loop while b # 0\n    nb = nb + 1\n    vol = vol + b_vol(b)\n    b = b_next(b)\n  endloop\n"
                      "  nc = 0\n  fn = 0.0\n  nsub = 0\n  local c = contact_head\n"
                      "  loop while c # 0\n"
                      "    nc = nc + 1\n"
                      "    local s = c_cx(c)\n"
                      "    loop while s # 0\n      fn = fn + cx_nforce(s)\n      nsub = nsub + 1\n      s = cx_next(s)\n    endloop\n"
                      "    c_extra(c) = 'seen'\n"
                      "    mark = c_extra(c)\n"
                      "    c = c_next(c)\n"
                      "  endloop\n"
                      "  top = b_near(1, 1, 0.5)\n"
                      "  topz = b_z(top)\n"
                      "end\n@sums"))
        << s.error();
    EXPECT_EQ(number(s, "nb"), 2);
    EXPECT_NEAR(number(s, "vol"), 5.0, 1e-12);
    EXPECT_EQ(number(s, "nc"), 1);
    EXPECT_GE(number(s, "nsub"), 4);
    EXPECT_NEAR(number(s, "fn"), 2000 * 10 * 1.0, 2000 * 10 * 1e-4);
    EXPECT_EQ(global(s, "mark").s, "seen");
    EXPECT_NEAR(number(s, "topz"), 0.5, 1e-3);
}

TEST(Fish, WalksOverZonesAndGridpoints) {
    Session s;
    ASSERT_TRUE(s.run("poly brick 0 1 0 1 0 1\nprop mat=1 dens=2000 ymod=1e9 prat=0.25\ngen edge 0.5\n"
                      "def count\n"
                      "  nz = 0\n  vol = 0\n  ng = 0\n  corners = 0\n"
                      "  local b = block_head\n"
                      "  local z = b_zone(b)\n"
                      "  loop while z # 0\n    nz = nz + 1\n    vol = vol + z_vol(z)\n    z = z_next(z)\n  endloop\n"
                      "  local g = b_gp(b)\n"
                      "  loop while g # 0\n    ng = ng + 1\n    g = gp_next(g)\n  endloop\n"
                      "  loop i (1, 4)\n    if z_gp(zone_head, i) # 0\n      corners = corners + 1\n    endif\n  endloop\n"
                      "  near = gp_x(gp_near(1, 1, 1)) + gp_y(gp_near(1, 1, 1)) + gp_z(gp_near(1, 1, 1))\n"
                      "end\n@count"))
        << s.error();
    EXPECT_EQ(number(s, "nz"), s.model.zones.size());
    EXPECT_NEAR(number(s, "vol"), 1.0, 1e-12);
    EXPECT_EQ(number(s, "ng"), s.model.gridpoints.size());
    EXPECT_EQ(number(s, "corners"), 4);
    EXPECT_NEAR(number(s, "near"), 3.0, 1e-12);
}

TEST(Fish, HistoriesOfFishFunctions) {
    Session s;
    ASSERT_TRUE(s.run("poly brick 0 1 0 1 0 1\nprop mat=1 dens=1000\ngrav 0 0 -10\nset dt 1e-3\ndamp off\n"
                      "def zpos\n  zpos = b_z(block_head)\nend\n"
                      "hist @zpos\nhist ncyc 1\nstep 100"))
        << s.error();
    const auto& h = s.model.histories.items.at(0);
    ASSERT_EQ(h.values.size(), 100u);
    // Free fall from rest: z = 0.5 - g t^2 / 2 (the leapfrog's positions are exact to O(dt)).
    const double t = 0.1;
    EXPECT_NEAR(h.values.back(), 0.5 - 10 * t * t / 2, 10 * 1e-3 * t);
    EXPECT_EQ(h.label, "@zpos");
}

TEST(Fish, ListPrintsNamesAndValues) {
    Session s;
    ASSERT_TRUE(s.run("@x = 2.5\ndef y\n  y = 'text'\nend\nlist @x y")) << s.error();
    EXPECT_NE(s.out.str().find("x = 2.5"), std::string::npos) << s.out.str();
    EXPECT_NE(s.out.str().find("y = text"), std::string::npos) << s.out.str();
}

TEST(Fish, FilesAreWrittenAndReadBack) {
    Session s;
    ASSERT_TRUE(s.run("def w\n"
                      "  array lines(3)\n"
                      "  lines(1) = 'first'\n  lines(2) = 2\n  lines(3) = 3.5\n"
                      "  st = open('fish-io.txt', 1, 1)\n  st2 = write(lines, 3)\n  st3 = close\n"
                      "  array back(3)\n"
                      "  st4 = open('fish-io.txt', 0, 1)\n  st5 = read(back, 3)\n  st6 = close\n"
                      "  r1 = back(1)\n  r3 = float(back(3))\n"
                      "end\n@w"))
        << s.error();
    EXPECT_EQ(number(s, "st"), 0);
    EXPECT_EQ(global(s, "r1").s, "first");
    EXPECT_EQ(number(s, "r3"), 3.5);
    std::remove("fish-io.txt");
}

TEST(Fish, OutPrintsALine) {
    Session s;
    ASSERT_TRUE(s.run("def f\n  ii = out('n = ' + string(3))\nend\n@f")) << s.error();
    EXPECT_EQ(s.out.str(), "n = 3\n");
}

TEST(Fish, ErrorsPointInsideTheFunctionWithTheCallChain) {
    Session s;
    EXPECT_FALSE(s.run("def inner\n  x = 1 / 0\nend\ndef outer\n  inner\nend\n@outer"));
    const std::string e = s.error();
    EXPECT_NE(e.find("t.dat:2:9: error: division by zero"), std::string::npos) << e;
    EXPECT_NE(e.find("in 'inner', called at t.dat:5"), std::string::npos) << e;
    EXPECT_NE(e.find("in 'outer', called at t.dat:7"), std::string::npos) << e;
}

TEST(Fish, TypeErrorsSayWhatToWrite) {
    Session s;
    EXPECT_FALSE(s.run("def f\n  s = 'n = ' + 3\nend\n@f"));
    EXPECT_NE(s.error().find("cannot use '+' on a string and an integer"), std::string::npos) << s.error();
    EXPECT_NE(s.error().find("string(x)"), std::string::npos) << s.error();
}

TEST(Fish, AFailedDefinitionKeepsTheOldOne) {
    Session s;
    ASSERT_TRUE(s.run("def f\n  f = 1\nend"));
    EXPECT_FALSE(s.run("def f\n  f = (2\nend"));
    EXPECT_NE(s.error().find("t.dat:2:9: error: expected ')'"), std::string::npos) << s.error();
    ASSERT_TRUE(s.run("@v = f")) << s.error();
    EXPECT_EQ(number(s, "v"), 1);
}

TEST(Fish, UnclosedBlocksAndStrayWordsAreErrors) {
    const struct {
        const char* text;
        const char* says;
    } cases[] = {
        {"def f\n  if 1 = 1 then\n    x = 1\nend", "this if has no 'endif'"},
        {"def f\n  loop i (1, 3)\nend", "this loop has no 'endloop'"},
        {"def f\n  endif\nend", "'endif' without the statement it closes"},
        {"def f\n  x = \nend", "expected a value"},
        {"def f\n  x = 'open\nend", "unterminated string"},
        {"def f\n  time = 3\nend", "'time' can be read, not assigned"},
        {"def sqrt\n  sqrt = 1\nend", "'sqrt' is a FISH intrinsic"},
        {"def f\n  x = sqrt(1, 2)\nend", "'sqrt' takes 1 argument, given 2"},
        {"def f\n  command\n    step 1\nend", "this command block has no 'endcommand'"},
    };
    for (const auto& c : cases) {
        Session s;
        EXPECT_FALSE(s.run(c.text)) << c.text;
        EXPECT_NE(s.error().find(c.says), std::string::npos) << c.text << "\n" << s.error();
    }
}

TEST(Fish, RunawayRecursionIsStopped) {
    Session s;
    EXPECT_FALSE(s.run("def f\n  f = g\nend\ndef g\n  g = f\nend\n@f"));
    EXPECT_NE(s.error().find("FISH calls nest more than"), std::string::npos) << s.error();
    // The session goes on.
    EXPECT_TRUE(s.run("@x = 1")) << s.error();
}

TEST(Fish, AFailingCommandStopsTheFunction) {
    Session s;
    EXPECT_FALSE(s.run("def f\n  reached = 0\n  command\n    poly brick 1 0 0 1 0 1\n  endcommand\n  reached = 1\nend\n@f"));
    EXPECT_NE(s.error().find("t.dat:4:"), std::string::npos) << s.error();
    EXPECT_NE(s.error().find("a command of this 'command' block failed"), std::string::npos) << s.error();
    EXPECT_EQ(number(s, "reached"), 0);
    EXPECT_EQ(s.model.blocks.size(), 0);
}

TEST(Fish, NewForgetsFish) {
    Session s;
    ASSERT_TRUE(s.run("@x = 1\nnew"));
    EXPECT_EQ(s.interp.fish().find("x"), nullptr);
}

TEST(Fish, PointersOfAChangedModelAreRefused) {
    Session s;
    EXPECT_FALSE(s.run("poly brick 0 1 0 1 0 1\n@b = block_head\ndelete range z 0 1\n@v = b_vol(@b)"));
    EXPECT_NE(s.error().find("that block no longer exists"), std::string::npos) << s.error();
}

TEST(Fish, WhilesteppingFunctionsRunEveryStep) {
    Session s;
    ASSERT_TRUE(s.run("poly brick 0 1 0 1 0 1\nprop mat=1 dens=1000\nset dt 1e-3\n"
                      "@count = 0\n"
                      "def counter\n  whilestepping\n  count = count + 1\nend\n"
                      "step 25"))
        << s.error();
    EXPECT_EQ(number(s, "count"), 25);
    // An error inside stops the cycle and says where.
    EXPECT_FALSE(s.run("def bad\n  whilestepping\n  x = 1 / 0\nend\nstep 5"));
    EXPECT_NE(s.error().find("a 'whilestepping' function failed"), std::string::npos) << s.error();
    EXPECT_NE(s.error().find("division by zero"), std::string::npos) << s.error();
}

TEST(Fish, DeepNestingIsRefusedNotACrash) {
    Session s;
    EXPECT_FALSE(s.run("def f\n  x = " + std::string(5000, '(') + "1" + std::string(5000, ')') + "\nend"));
    EXPECT_NE(s.error().find("nests more than"), std::string::npos) << s.error();
    EXPECT_FALSE(s.run("def g\n  x = " + std::string(5000, '-') + "1\nend"));
    EXPECT_NE(s.error().find("nests more than"), std::string::npos) << s.error();
    std::string deep = "def h\n";
    for (int i = 0; i < 3000; ++i) deep += "if 1 = 1\n";
    for (int i = 0; i < 3000; ++i) deep += "endif\n";
    EXPECT_FALSE(s.run(deep + "end"));
    EXPECT_NE(s.error().find("nests more than"), std::string::npos) << s.error();
    EXPECT_TRUE(s.run("@ok = 1")) << s.error();
}

TEST(Fish, BareNamesInCommandsTakeTheirValuesAsInUdec) {
    Session s;
    ASSERT_TRUE(s.run("def params\n  top = 2.0\n  fName = 'bare'\n  disp = 9\nend\n@params\n"
                      "poly brick 0 1 0 1 0 top\nsave fName\nreset disp"))
        << s.error();
    EXPECT_NEAR(s.model.blocks.centroid[0].z(), 1.0, 1e-12);
    std::ifstream saved("bare.sav");
    EXPECT_TRUE(saved.good());
    std::remove("bare.sav");
    // A word the command knows ('disp' of 'reset') is never replaced.
}

TEST(Fish, RecursionWithoutLoopsIsBoundedToo) {
    // About 2^60 calls, never more than 61 deep: the budget counts calls as well as loops.
    Session s;
    s.interp.limits.fish_steps = 5000;
    EXPECT_FALSE(s.run("def f(n)\n  if n > 0 then\n    a = f(n - 1) + f(n - 1)\n  endif\nend\n@f(60)"));
    EXPECT_NE(s.error().find("bound on FISH loop iterations and calls"), std::string::npos) << s.error();
}

TEST(Fish, LoopsEndAtTheLargestIntegerAndRefuseUnendingFloatBounds) {
    Session s;
    ASSERT_TRUE(s.run("def f\n  n = 0\n  loop i (9223372036854775806, 9223372036854775807)\n    n = n + 1\n  endloop\nend\n@f"))
        << s.error();
    EXPECT_EQ(s.interp.fish().find("n")->value.number(), 2);
    EXPECT_FALSE(s.run("def g\n  loop x (1e300, 2e300)\n  endloop\nend\n@g"));
    EXPECT_NE(s.error().find("within +/-9e15"), std::string::npos) << s.error();
}

TEST(Fish, AllArraysTogetherAreBounded) {
    Session s;
    s.interp.fish().max_array_items = 1000;
    ASSERT_TRUE(s.run("def a1\n  array one(600)\nend")) << s.error();
    EXPECT_FALSE(s.run("def a2\n  array two(600)\nend"));
    EXPECT_NE(s.error().find("beyond 1000"), std::string::npos) << s.error();
    ASSERT_TRUE(s.run("def a3\n  array one(900)\nend")) << s.error(); // a redefinition replaces
    EXPECT_FALSE(s.run("def a4\n  array big(1e300)\nend"));
    EXPECT_NE(s.error().find("elements along a dimension"), std::string::npos) << s.error();
}

TEST(Fish, WorkIsBoundedWhereTheSessionAsksAndStringsAreCapped) {
    Session s;
    s.interp.limits.fish_steps = 1000;
    EXPECT_FALSE(s.run("def spin\n  loop while 1 = 1\n  endloop\nend\n@spin"));
    EXPECT_NE(s.error().find("bound on FISH loop iterations"), std::string::npos) << s.error();
    Session t;
    EXPECT_FALSE(t.run("def grow\n  s = 'x'\n  loop i (1, 30)\n    s = s + s\n  endloop\nend\n@grow"));
    EXPECT_NE(t.error().find("a string of more than 1048576 characters"), std::string::npos) << t.error();
    EXPECT_FALSE(t.run("def big\n  array a(100000, 1000)\nend"));
    EXPECT_NE(t.error().find("more than 10000000 elements"), std::string::npos) << t.error();
}

TEST(Fish, DefineAndExitAsClassicScriptsWriteThem) {
    // 'define' is 'def'; 'exit' leaves the function at once (3DEC 4); 'return' too.
    Session s;
    ASSERT_TRUE(s.run("define early(n)\n  early = 1\n  if n > 2 then\n    exit\n  endif\n  early = 2\nend\n"
                      "def late\n  late = 10\n  return\n  late = 20\nend\n"
                      "def both\n  a = early(5)\n  b = early(1)\n  c = late\nend\n@both"))
        << s.error();
    EXPECT_EQ(number(s, "a"), 1);
    EXPECT_EQ(number(s, "b"), 2);
    EXPECT_EQ(number(s, "c"), 10);
}

TEST(Fish, HistoriesOfBareFishNames) {
    // `hist zpos` and `hist kv` as UDEC and 3DEC 4 write them: a function, and a variable
    // that a command set; a name that is a keyword of 'hist' keeps its meaning.
    Session s;
    ASSERT_TRUE(s.run("poly brick 0 1 0 1 0 1\nprop mat=1 dens=1000\ngrav 0 0 -10\nset dt 1e-3\ndamp off\n"
                      "def zpos\n  zpos = b_z(block_head)\nend\nset kv = 3\n"
                      "hist zpos\nhist kv\nhist nblock\nhist ncyc 1\nstep 100"))
        << s.error();
    ASSERT_EQ(s.model.histories.items.size(), 3u);
    EXPECT_EQ(s.model.histories.items.at(2).values.back(), 1); // an intrinsic, read each sample
    const auto& h = s.model.histories.items.at(0);
    ASSERT_EQ(h.values.size(), 100u);
    const double t = 0.1;
    EXPECT_NEAR(h.values.back(), 0.5 - 10 * t * t / 2, 10 * 1e-3 * t);
    EXPECT_EQ(s.model.histories.items.at(1).values.back(), 3);
    EXPECT_FALSE(s.run("hist nosuch"));
    EXPECT_NE(s.error().find("unknown keyword 'nosuch'"), std::string::npos) << s.error();
}

TEST(Fish, ClassicRangeNamesAndHiddenBlocksInChange) {
    // rkn2's pattern: hide all, show two blocks by 'bid', change the joint material of the
    // contact between them only; 'zr' is 3DEC's z range.
    Session s;
    ASSERT_TRUE(s.run("poly brick 0 1 0 1 0 1\npoly brick 0 1 1 2 0 1\npoly brick 0 1 0 2 -1 0\n"
                      "prop mat=1 dens=2000\nprop jmat=1 jkn=1e10 jks=1e10 jfric=30\nprop jmat=2 jkn=1e10 jks=1e10 jfric=40\n"
                      "def pick\n  b1 = 1\n  b2 = 2\n  command\n    hide\n    show range bid @b1\n    show range bid @b2\n"
                      "    change jmat 2\n    show\n  endcommand\nend\n@pick\n"
                      "def count\n  n2 = 0\n  c = contact_head\n  loop while c # 0\n"
                      "    if c_jmat(c) = 2 then\n      n2 = n2 + 1\n      side = c_ny(c)\n    endif\n    c = c_next(c)\n  endloop\nend\n@count\n"
                      "fix range zr -1 0"))
        << s.error();
    EXPECT_EQ(number(s, "n2"), 1);
    EXPECT_NEAR(std::fabs(number(s, "side")), 1.0, 1e-12); // the contact between blocks 1 and 2
    int fixed = 0;
    for (int b = 0; b < s.model.blocks.size(); ++b) fixed += (s.model.blocks.flags[b] & odec::kFixed) ? 1 : 0;
    EXPECT_EQ(fixed, 1);
}
