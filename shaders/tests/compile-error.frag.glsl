// A fragment shader with a mistake on line 6, for the test that compile errors name the file
// and the line. Not used by anything else.
out vec4 fragmentColor;
void main()
{
    fragmentColor = vec4(undeclaredColor, 1.0);
}
