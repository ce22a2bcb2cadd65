package mapm.testutil

import org.scalatest.Assertions

/** Mixed into suites that read `../shared`: `requireShared("vectors/x.csv")` cancels the test
  * (reported as canceled, not failed) with a clear message when the file is absent. */
trait SharedFiles { this: Assertions =>
  def requireShared(rel: String): java.nio.file.Path = {
    val p = SharedDir.file(rel)
    if (!java.nio.file.Files.exists(p))
      cancel(s"skipped: ${p} is absent (the ../shared folder beside the project holds it; set MAPM_SHARED to point elsewhere)")
    p
  }
}
