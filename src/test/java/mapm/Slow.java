package mapm;

import java.lang.annotation.ElementType;
import java.lang.annotation.Retention;
import java.lang.annotation.RetentionPolicy;
import java.lang.annotation.Target;
import org.scalatest.TagAnnotation;

/**
 * Marks a spec class (all its tests) or a test method as slow: millions of operations, Verilator
 * builds of whole MAPMs, many seeds or cost-flow synthesis. The quick run leaves them out:
 * {@code tools/sbt "testOnly -- -l mapm.Slow"}; {@code tools/sbt test} runs everything.
 */
@TagAnnotation
@Retention(RetentionPolicy.RUNTIME)
@Target({ElementType.METHOD, ElementType.TYPE})
public @interface Slow {}
