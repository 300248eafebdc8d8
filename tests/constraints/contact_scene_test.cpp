// Mistakes in [[obstacle]] and [[contact]] tables: one line naming file:line:col and key,
// what was expected and what was found.
#include <gtest/gtest.h>

#include "constraints/contact_scene.hpp"
#include "constraints/contact_set.hpp"
#include "core/model.hpp"
#include "core/errors.hpp"

using namespace c2d;
using namespace c2d::constraints;

namespace {

const char* kBase =
    "[[material]]\nname = \"steel\"\nE = 210000.0\nnu = 0.3\n"
    "[[body]]\nname = \"b\"\nmaterial = \"steel\"\n"
    "shape = { type = \"rectangle\", min = [0.0, 0.0], max = [1.0, 1.0] }\nmesh = { size = 0.5 }\n"
    "[[obstacle]]\nname = \"floor\"\ntype = \"line\"\npoint = [0.0, 0.0]\nnormal = [0.0, 1.0]\n";

std::string contact_error(const std::string& extra, const std::string& method = "") {
  try {
    const core::Scene s = core::parse_scene(std::string(kBase) + extra, "bad.toml");
    parse_contact_scene(s, method);
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    return msg;
  }
  return "no error";
}

}  // namespace

TEST(ContactScene, ValidTablesParse) {
  const core::Scene s = core::parse_scene(
      std::string(kBase) +
          "[[contact]]\nslave = { body = \"b\", edge = \"bottom\" }\nmaster = { obstacle = "
          "\"floor\" }\nmethod = \"auglag\"\npenalty = { factor = 100.0 }\ntolerance = 1e-9\n",
      "ok.toml");
  const ContactSceneSpec spec = parse_contact_scene(s);
  ASSERT_EQ(spec.pairs.size(), 1u);
  EXPECT_EQ(spec.pairs[0].obstacle, 0);
  EXPECT_EQ(spec.options.method, "auglag");
  EXPECT_DOUBLE_EQ(spec.options.penalty_factor, 100.0);
  EXPECT_DOUBLE_EQ(spec.options.tolerance, 1e-9);
  EXPECT_EQ(parse_contact_scene(s, "ssn").options.method, "ssn");  // --method wins
}

TEST(ContactScene, MistakesAreOneLineWithPlaceAndExpectation) {
  const std::string slave = "slave = { body = \"b\", edge = \"bottom\" }\n";
  std::string m = contact_error("[[contact]]\n" + slave + "master = { obstacle = \"flor\" }\n");
  EXPECT_NE(m.find("bad.toml:"), std::string::npos) << m;
  EXPECT_NE(m.find("did you mean 'floor'"), std::string::npos) << m;
  m = contact_error("[[contact]]\n" + slave + "master = { obstacle = \"floor\" }\nmethod = \"newton\"\n");
  EXPECT_NE(m.find("contact[0].method"), std::string::npos) << m;
  EXPECT_NE(m.find("newton"), std::string::npos) << m;
  m = contact_error("[[contact]]\nmaster = { obstacle = \"floor\" }\n");
  EXPECT_NE(m.find("contact[0].slave"), std::string::npos) << m;
  m = contact_error("[[contact]]\n" + slave + "master = { obstacle = \"floor\" }\npenalty = { kk = 1.0 }\n");
  EXPECT_NE(m.find("kk"), std::string::npos) << m;
  m = contact_error("[[contact]]\n" + slave + "master = { obstacle = \"floor\" }\n", "bogus");
  EXPECT_NE(m.find("found 'bogus'"), std::string::npos) << m;
  m = contact_error("[[obstacle]]\nname = \"c\"\ntype = \"circle\"\ncenter = [0.0, 0.0]\nradius = -1.0\n");
  EXPECT_NE(m.find("obstacle[1].radius"), std::string::npos) << m;
}

// Issue 16, finding 5: a contact master naming a missing body used to take the edge from every
// body; a repeated contact name was accepted.
TEST(ContactScene, MasterBodyTypoAndDuplicateNamesAreRefused) {
  const std::string two_bodies = std::string(kBase) +
      "[[body]]\nname = \"punch\"\nmaterial = \"steel\"\n"
      "shape = { type = \"rectangle\", min = [0.0, 1.0], max = [1.0, 2.0] }\nmesh = { size = 0.5 }\n";
  const core::Scene s = core::parse_scene(
      two_bodies + "[[contact]]\nslave = { body = \"b\", edge = \"top\" }\n"
                   "master = { body = \"punsh\", edge = \"bottom\" }\n",
      "typo.toml");
  const core::Model model = core::build_model(s);
  try {
    const ContactSet contact(model, parse_contact_scene(s), s);
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("typo.toml:"), std::string::npos) << msg;
    EXPECT_NE(msg.find("found 'punsh'"), std::string::npos) << msg;
    EXPECT_NE(msg.find("did you mean 'punch'"), std::string::npos) << msg;
  }
  const std::string pair = "[[contact]]\nname = \"c\"\nslave = { body = \"b\", edge = \"bottom\" }\n"
                           "master = { obstacle = \"floor\" }\n";
  const std::string m = contact_error(pair + pair);
  EXPECT_NE(m.find("contact[1].name"), std::string::npos) << m;
  EXPECT_NE(m.find("a unique [[contact]] name"), std::string::npos) << m;
}

// [[constraint]] mistakes (issue 17): the same one-line, located refusals.
TEST(ContactScene, ConstraintMistakesAreLocated) {
  std::string m = contact_error(
      "[[constraint]]\ntype = \"equal\"\non = { body = \"b\", edge = \"top\" }\ndof = \"uz\"\n");
  EXPECT_NE(m.find("constraint[0].dof"), std::string::npos) << m;
  EXPECT_NE(m.find("found string \"uz\""), std::string::npos) << m;
  m = contact_error("[[constraint]]\ntype = \"glue\"\n");
  EXPECT_NE(m.find("constraint[0].type"), std::string::npos) << m;
  m = contact_error("[[constraint]]\ntype = \"linear\"\nterms = [ { on = { nearest = [0.0, 0.0] }, "
                    "dof = \"ux\", coefficient = 0.0 } ]\n");
  EXPECT_NE(m.find("coefficient"), std::string::npos) << m;
  EXPECT_NE(m.find("non-zero"), std::string::npos) << m;
  m = contact_error("[[constraint]]\ntype = \"equal\"\non = { body = \"b\", edge = \"top\" }\n"
                    "dof = \"ux\"\nmethod = \"penalty\"\n[[contact]]\n"
                    "slave = { body = \"b\", edge = \"bottom\" }\nmaster = { obstacle = \"floor\" }\n"
                    "method = \"lagrange\"\n");
  // (contacts are read first, whatever the order in the file)
  EXPECT_NE(m.find("constraint[0].method"), std::string::npos) << m;
  EXPECT_NE(m.find("the same method as the first [[contact]]"), std::string::npos) << m;
  // A linear term must select exactly one node: refused when the set is built.
  const core::Scene s = core::parse_scene(
      std::string(kBase) + "[[constraint]]\ntype = \"linear\"\nterms = [ { on = { body = \"b\", "
                           "edge = \"top\" }, dof = \"uy\", coefficient = 1.0 } ]\n",
      "terms.toml");
  const core::Model model = core::build_model(s);
  try {
    const ContactSet set(model, parse_contact_scene(s), s);
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("terms.toml:"), std::string::npos) << msg;
    EXPECT_NE(msg.find("must select one node"), std::string::npos) << msg;
  }
}
