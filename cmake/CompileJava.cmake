# Compiles every .java file below SRC into OUT with classpath CP.
file(GLOB_RECURSE sources ${SRC}/*.java)
execute_process(COMMAND ${JAVAC} -nowarn -source 8 -target 8 -cp ${CP} -d ${OUT} ${sources}
                RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "javac failed on the generated nadir types")
endif()
