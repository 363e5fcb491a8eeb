//! @file VerifiedImageTests.cpp
//! @brief VerifiedImage: only the verifier makes one; a failed verification leaves the image
//!        with its owner; isosim refuses what the verifier refuses, with its reason.
#include <string>

#include <doctest/doctest.h>

#include "BadImages.h"
#include "TestUtil.h"
#include "image/ImageVerifier.h"

using namespace iso;
using namespace iso::test;

TEST_CASE("image: verifyImage(Image&&) takes a valid image and leaves an invalid one") {
  image::Image good = mainOnly(Asm().stmt().push(7).storeR(1).stmt().op(Op::End));
  const size_t codeSize = good.code.size();
  image::ImageError err;
  std::optional<image::VerifiedImage> v = image::verifyImage(std::move(good), err);
  REQUIRE_MESSAGE(v.has_value(), err.message);
  CHECK(v->image().code.size() == codeSize);
  CHECK(v->instructions() == 5); // stmt, push.d0, store.r, stmt, end
  // the boundaries the verifier found: stmt 0, push.d0 1, store.r 3, stmt 5, end 6
  CHECK(v->boundaries().count() == 5);
  for (size_t off = 0; off < codeSize; ++off)
    CHECK(v->boundaries().test(off) == (off == 0 || off == 1 || off == 3 || off == 5 || off == 6));
  CHECK(v->boundaries().rank(5) == 3);

  image::Image bad = mainOnly(Asm().stmt().jump(Op::Jump, "@2").stmt().op(Op::End));
  const image::Image copy = bad;
  CHECK_FALSE(image::verifyImage(std::move(bad), err).has_value());
  CHECK(err.message.find("not an instruction boundary") != std::string::npos);
  CHECK(bad.code == copy.code); // still there, for a listing
  CHECK(bad.procs.size() == copy.procs.size());
}

TEST_CASE("image: both verifyImage overloads give the same first error for every bad image") {
  for (const BadImage& b : badImages()) {
    CAPTURE(b.name);
    image::Image img = b.make();
    image::ImageError byRef, byValue;
    CHECK_FALSE(image::verifyImage(img, byRef));
    CHECK_FALSE(image::verifyImage(image::Image(img), byValue).has_value());
    CHECK(byRef.message == byValue.message);
    CHECK(byRef.offset == byValue.offset);
  }
}

TEST_CASE("image: the z32 instructions need the z32 flag, and m.special its call") {
  image::ImageError err;
  image::Image ok = withSub(Asm()
                                .stmt()
                                .op(Op::MSpecial)
                                .uleb(6)
                                .call(1)
                                .stmt()
                                .op(Op::M1)
                                .stmt()
                                .push(5)
                                .op(Op::Aux)
                                .byte(0)
                                .byte(0)
                                .stmt()
                                .op(Op::End));
  ok.flags |= image::Image::kFlagZ32;
  CHECK_MESSAGE(image::verifyImage(ok, err), err.message);

  image::Image noFlag = ok;
  noFlag.flags &= ~image::Image::kFlagZ32;
  CHECK_FALSE(image::verifyImage(noFlag, err));
  CHECK(err.message.find("without the z32 flag") != std::string::npos);

  image::Image stray = withSub(Asm().stmt().op(Op::MSpecial).uleb(6).stmt().call(1).stmt().op(Op::End));
  stray.flags |= image::Image::kFlagZ32;
  CHECK_FALSE(image::verifyImage(stray, err));
  CHECK(err.message.find("m.special must be followed by the call") != std::string::npos);
}
