# Writes the bash and zsh completions and the man page of the layerlab program
# from its own parser: cmake -DLAYERLAB=PATH -DOUT=DIR -P write_cli_documents.cmake
foreach(document "layerlab.bash;--completion;bash" "_layerlab;--completion;zsh" "layerlab.1;--man")
  list(POP_FRONT document file)
  execute_process(COMMAND ${LAYERLAB} help ${document} OUTPUT_FILE ${OUT}/${file}.new RESULT_VARIABLE status
                  ERROR_VARIABLE error)
  if(NOT status EQUAL 0)
    message(FATAL_ERROR "layerlab help ${document} failed (${status}): ${error}")
  endif()
  file(RENAME ${OUT}/${file}.new ${OUT}/${file})
endforeach()
