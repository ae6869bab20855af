// docs/scene-format.md is generated from the parameter declarations; this fails when it is stale.
#include <gtest/gtest.h>

#include "sphfx/core/frame_files.h"
#include "sphfx/core/scene.h"

TEST(SchemaDoc, CommittedReferenceIsCurrent) {
  const std::string committed = sphfx::readTextFile(std::string(SPHFX_SOURCE_DIR) + "/docs/scene-format.md");
  EXPECT_EQ(committed, sphfx::sceneReferenceMarkdown())
      << "docs/scene-format.md is stale: regenerate it with `sphfx scene --schema > docs/scene-format.md`";
}

TEST(SchemaDoc, EveryParameterHasDescriptionAndDefault) {
  std::vector<sphfx::schema::FieldDoc> docs;
  sphfx::sceneSchema().document("", docs);
  EXPECT_GT(docs.size(), 60u);
  for (const auto& d : docs) {
    EXPECT_FALSE(d.description.empty()) << d.path;
    EXPECT_FALSE(d.defaultValue.empty()) << d.path;
  }
}
